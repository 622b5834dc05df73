// printable_text: what an instrument sends is stored and shown without terminal controls and
// as valid UTF-8.
#include <string>

#include <gtest/gtest.h>

#include "tocd/core/printable.hpp"

using tocd::printable_text;

namespace {
const std::string kFffd = "\xEF\xBF\xBD";
}

TEST(PrintableText, PrintableAsciiAndValidUtf8AreKept) {
  EXPECT_EQ(printable_text("Thorlabs PM100USB, fw 1.7.0"), "Thorlabs PM100USB, fw 1.7.0");
  EXPECT_EQ(printable_text("Zwick \xC2\xB5m \xE2\x82\xAC \xF0\x9F\x94\xAC"),
            "Zwick \xC2\xB5m \xE2\x82\xAC \xF0\x9F\x94\xAC");
  EXPECT_EQ(printable_text(""), "");
}

TEST(PrintableText, ControlCharactersAreReplaced) {
  EXPECT_EQ(printable_text("a\x1B[2Jb"), "a" + kFffd + "[2Jb");  // ESC: clear screen
  EXPECT_EQ(printable_text("x\ty\nz\r\x7F"), "x" + kFffd + "y" + kFffd + "z" + kFffd + kFffd);
  EXPECT_EQ(printable_text("\xC2\x9B"
                           "31m"),
            kFffd + "31m");  // C1 CSI, valid UTF-8
  EXPECT_EQ(printable_text(std::string("a\0b", 3)), "a" + kFffd + "b");
}

TEST(PrintableText, InvalidUtf8BecomesReplacementCharacters) {
  EXPECT_EQ(printable_text("ab\xFF"), "ab" + kFffd);
  EXPECT_EQ(printable_text("\xC3"), kFffd);                                      // truncated sequence
  EXPECT_EQ(printable_text("\xC0\xAF"), kFffd + kFffd);                          // overlong '/'
  EXPECT_EQ(printable_text("\xED\xA0\x80"), kFffd + kFffd + kFffd);              // surrogate
  EXPECT_EQ(printable_text("\xF4\x90\x80\x80"), kFffd + kFffd + kFffd + kFffd);  // > U+10FFFF
  EXPECT_EQ(printable_text("\xE2\x82Z"), kFffd + kFffd + "Z");  // the byte after a bad one survives
}

TEST(PrintableText, BidirectionalFormattingCharactersAreReplaced) {
  // U+202E (right-to-left override) would show "run 1 \u202Egol.exe" as "run 1 exe.log".
  EXPECT_EQ(printable_text("a\xE2\x80\xAE"
                           "b"),
            "a\xEF\xBF\xBD"
            "b");
  EXPECT_EQ(printable_text("\xE2\x81\xA6x\xE2\x81\xA9"), "\xEF\xBF\xBDx\xEF\xBF\xBD");  // U+2066, U+2069
  EXPECT_EQ(printable_text("\xE2\x80\x8F"), "\xEF\xBF\xBD");                            // U+200F
  // Neighbours that are ordinary text stay: U+2029 (paragraph separator) is not touched here,
  // U+2030 (per mille) is printable.
  EXPECT_EQ(printable_text("\xE2\x80\xB0"), "\xE2\x80\xB0");
}
