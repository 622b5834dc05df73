#include <gtest/gtest.h>

#include "tocd/devices/usbtmc.hpp"

using namespace tocd::devices;
namespace tmc = tocd::devices::usbtmc;
using Bytes = std::vector<std::uint8_t>;

TEST(UsbtmcFraming, DevDepMsgOutHeaderAndPadding) {
  const std::string msg = "*IDN?\n";  // 6 bytes -> 12 + 6 = 18 -> padded to 20
  const Bytes t =
      tmc::encode_dev_dep_msg_out(1, {reinterpret_cast<const std::uint8_t*>(msg.data()), msg.size()}, true);
  const Bytes expected{0x01, 0x01, 0xFE, 0x00, 0x06, 0x00, 0x00, 0x00, 0x01, 0x00,
                       0x00, 0x00, '*',  'I',  'D',  'N',  '?',  '\n', 0x00, 0x00};
  EXPECT_EQ(t, expected);
  // Without EOM and already aligned: no padding, attribute byte 0.
  const std::string four = "ABCD";
  const Bytes u = tmc::encode_dev_dep_msg_out(
      0x80, {reinterpret_cast<const std::uint8_t*>(four.data()), four.size()}, false);
  EXPECT_EQ(u.size(), 16u);
  EXPECT_EQ(u[1], 0x80);
  EXPECT_EQ(u[2], 0x7F);
  EXPECT_EQ(u[8], 0x00);
}

TEST(UsbtmcFraming, RequestDevDepMsgIn) {
  const auto t = tmc::encode_request_dev_dep_msg_in(255, 0x01020304);
  EXPECT_EQ(Bytes(t.begin(), t.end()),
            (Bytes{0x02, 0xFF, 0x00, 0x00, 0x04, 0x03, 0x02, 0x01, 0x00, 0x00, 0x00, 0x00}));
}

TEST(UsbtmcFraming, TagsSkipZero) {
  EXPECT_EQ(tmc::next_tag(0), 1);
  EXPECT_EQ(tmc::next_tag(1), 2);
  EXPECT_EQ(tmc::next_tag(255), 1);
}

namespace {
Bytes in_transfer(std::uint8_t tag, const std::string& data, bool eom) {
  Bytes t{0x02,
          tag,
          static_cast<std::uint8_t>(~tag),
          0,
          static_cast<std::uint8_t>(data.size()),
          0,
          0,
          0,
          static_cast<std::uint8_t>(eom ? 1 : 0),
          0,
          0,
          0};
  t.insert(t.end(), data.begin(), data.end());
  while (t.size() % 4) t.push_back(0);
  return t;
}

void expect_rejected(const Bytes& t, std::uint8_t tag, const std::string& words) {
  try {
    tmc::decode_dev_dep_msg_in(t, tag, 64);
    ADD_FAILURE() << "accepted a transfer that should fail with: " << words;
  } catch (const LinkError& e) {
    EXPECT_EQ(e.kind(), LinkFailure::protocol);
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(UsbtmcFraming, DecodesAValidResponse) {
  const auto h = tmc::decode_dev_dep_msg_in(in_transfer(7, "1.0E-3\n", true), 7, 64);
  EXPECT_EQ(h.tag, 7);
  EXPECT_EQ(h.transfer_size, 7u);
  EXPECT_TRUE(h.eom);
}

TEST(UsbtmcFraming, RejectsEachHeaderDefect) {
  expect_rejected(Bytes{0x02, 0x07, 0xF8}, 7, "shorter than the 12-byte header");
  Bytes wrong_id = in_transfer(7, "x", true);
  wrong_id[0] = 0x01;
  expect_rejected(wrong_id, 7, "MsgID 1");
  expect_rejected(in_transfer(8, "x", true), 7, "bTag 8 does not echo the request's bTag 7");
  Bytes inverse = in_transfer(7, "x", true);
  inverse[2] = 0x00;
  expect_rejected(inverse, 7, "not the inverse");
  Bytes reserved = in_transfer(7, "x", true);
  reserved[3] = 1;
  expect_rejected(reserved, 7, "reserved");
  Bytes truncated = in_transfer(7, "12345678", true);
  truncated.resize(16);
  expect_rejected(truncated, 7, "only 4 data bytes");
  EXPECT_THROW(tmc::decode_dev_dep_msg_in(in_transfer(7, "12345678", true), 7, 4), LinkError);  // oversize
}
