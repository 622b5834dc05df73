#include <gtest/gtest.h>

#include "tocd/devices/scpi_client.hpp"

using namespace tocd::devices;

namespace {
double parse(std::string_view s) {
  return parse_scpi_number(s, "meter", "MEAS:POW?");
}
}  // namespace

TEST(ScpiNumber, AcceptsNr1Nr2Nr3) {
  EXPECT_DOUBLE_EQ(parse("42"), 42.0);
  EXPECT_DOUBLE_EQ(parse("+1.5"), 1.5);
  EXPECT_DOUBLE_EQ(parse("-.25"), -0.25);
  EXPECT_DOUBLE_EQ(parse("1.234560E-04"), 1.23456e-4);
  EXPECT_DOUBLE_EQ(parse(" 9.9E+37 \r\n"), 9.9e37);
  EXPECT_DOUBLE_EQ(parse("5."), 5.0);
}

TEST(ScpiNumber, RejectsWhatIsNotANumberAndQuotesIt) {
  for (const char* bad : {"", "OVERLOAD", "1.0 W", "nan", "inf", "1e", "--1", ".", "0x10", "1,2", "E5"}) {
    try {
      parse(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const ProtocolError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("meter"), std::string::npos) << msg;
      EXPECT_NE(msg.find("MEAS:POW?"), std::string::npos) << msg;
      EXPECT_NE(msg.find(std::string("\"") + bad), std::string::npos) << msg;
    }
  }
}

TEST(ScpiNumber, EscapesNonTextBytesInTheMessage) {
  try {
    parse(std::string("\x01\xFF", 2));
    FAIL();
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("\\x01\\xFF"), std::string::npos) << e.what();
  }
}

TEST(ScpiError, ParsesQueueEntries) {
  const auto e = parse_scpi_error("-222,\"Data out of range\"", "meter");
  EXPECT_EQ(e.code, -222);
  EXPECT_EQ(e.message, "Data out of range");
  EXPECT_EQ(parse_scpi_error("+0,\"No error\"", "meter").code, 0);
  EXPECT_THROW(parse_scpi_error("no error", "meter"), ProtocolError);
  EXPECT_THROW(parse_scpi_error("-1x,\"a\"", "meter"), ProtocolError);
  EXPECT_THROW(parse_scpi_error("-1,unquoted", "meter"), ProtocolError);
}
