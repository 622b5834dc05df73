// The SCPI server's line cutting: every byte looked at once, however the line is split.
#include <ctime>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "net/line_scanner.hpp"

using tocd::mocks::net::LineScanner;

namespace {

double thread_cpu_s() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

TEST(LineScanner, CutsLinesSplitAnywhereAndDropsCarriageReturns) {
  const std::string stream = "*IDN?\r\nMEAS?\n\nSENS:CORR:WAV 800;*OPC?\r\n*RST";
  for (std::size_t piece = 1; piece <= stream.size(); ++piece) {
    LineScanner scanner;
    std::string input;
    std::vector<std::string> lines;
    for (std::size_t at = 0; at < stream.size(); at += piece) {
      input += stream.substr(at, piece);
      ASSERT_TRUE(scanner.take_lines(input, [&](std::string_view l) {
        lines.emplace_back(l);
        return true;
      }));
    }
    EXPECT_EQ(lines, (std::vector<std::string>{"*IDN?", "MEAS?", "", "SENS:CORR:WAV 800;*OPC?"}))
        << "pieces of " << piece;
    EXPECT_EQ(input, "*RST");  // the unfinished line stays
    EXPECT_EQ(scanner.scanned(), 4u);
  }
}

TEST(LineScanner, StopsAtTheLineItsCallerRefuses) {
  LineScanner scanner;
  std::string input = "a\nb\nc\n";
  int seen = 0;
  EXPECT_FALSE(scanner.take_lines(input, [&](std::string_view l) { return ++seen, l != "b"; }));
  EXPECT_EQ(seen, 2);
}

// 16 MiB without a newline arriving in 4 KiB pieces: searching the whole buffer after every
// piece looked at 32 GiB (seconds of CPU); remembering where the search stopped looks at 16 MiB.
TEST(LineScanner, SixteenMebibyteLineInSmallPiecesCostsLinearTime) {
  LineScanner scanner;
  std::string input;
  const std::string piece(4096, 'x');
  int lines = 0;
  const auto count = [&](std::string_view) { return ++lines, true; };
  const double t0 = thread_cpu_s();
  for (int i = 0; i < 4096; ++i) {
    input += piece;
    scanner.take_lines(input, count);
  }
  const double cpu_s = thread_cpu_s() - t0;
  std::printf("16 MiB line in 4 KiB pieces: %.4f s CPU\n", cpu_s);
  EXPECT_EQ(lines, 0);
  EXPECT_EQ(scanner.scanned(), 16u * 1024 * 1024);
  EXPECT_LT(cpu_s, 0.25);
  input += "\n";
  std::size_t length = 0;
  scanner.take_lines(input, [&](std::string_view l) { return length = l.size(), true; });
  EXPECT_EQ(length, 16u * 1024 * 1024);
  EXPECT_TRUE(input.empty());
}
