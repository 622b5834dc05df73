// USBTMC on the wire: the exact bytes of a request and of a multi-transfer response, the
// simulated device's byte-for-byte checks, and the host's answer to bad device framing.
#include <vector>

#include "pm_fixture.hpp"
#include "tocd/devices/usbtmc.hpp"

using namespace tocd::devices;
using Bytes = std::vector<std::uint8_t>;

namespace {

/// Forwards to the simulated device and keeps a copy of every bulk transfer.
class Recorder final : public UsbBulkEndpoint {
 public:
  Recorder(std::unique_ptr<UsbBulkEndpoint> inner, std::vector<Bytes>* out, std::vector<Bytes>* in)
      : inner_(std::move(inner)), out_(out), in_(in) {}
  std::string describe() const override { return inner_->describe(); }
  std::uint8_t interface_number() const override { return inner_->interface_number(); }
  std::uint8_t bulk_out_address() const override { return inner_->bulk_out_address(); }
  std::uint8_t bulk_in_address() const override { return inner_->bulk_in_address(); }
  UsbTransfer bulk_out(std::span<const std::uint8_t> d, std::chrono::milliseconds t) override {
    out_->emplace_back(d.begin(), d.end());
    return inner_->bulk_out(d, t);
  }
  UsbTransfer bulk_in(std::span<std::uint8_t> b, std::chrono::milliseconds t) override {
    const auto r = inner_->bulk_in(b, t);
    if (r.status == UsbStatus::ok)
      in_->emplace_back(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(r.length));
    return r;
  }
  UsbTransfer control_in(const UsbControlRequest& r, std::span<std::uint8_t> b,
                         std::chrono::milliseconds t) override {
    return inner_->control_in(r, b, t);
  }
  UsbTransfer clear_halt(std::uint8_t a) override { return inner_->clear_halt(a); }

 private:
  std::unique_ptr<UsbBulkEndpoint> inner_;
  std::vector<Bytes>* out_;
  std::vector<Bytes>* in_;
};

Bytes header(std::uint8_t id, std::uint8_t tag, std::uint32_t size, std::uint8_t attr) {
  return {id, tag, static_cast<std::uint8_t>(~tag), 0, static_cast<std::uint8_t>(size), 0, 0, 0, attr, 0,
          0,  0};
}

Bytes cat(Bytes a, const std::string& s, std::size_t pad_to) {
  a.insert(a.end(), s.begin(), s.end());
  a.resize(pad_to, 0);
  return a;
}

auto deadline() {
  return Clock::now() + std::chrono::seconds{2};
}

/// `*OPC?` sent and its answer `1` read back, transfer for transfer: the endpoint works.
void expect_opc_answered(UsbBulkEndpoint& ep) {
  ASSERT_EQ(ep.bulk_out(cat(header(1, 7, 6, 1), "*OPC?\n", 20), std::chrono::milliseconds{50}).status,
            UsbStatus::ok);
  ASSERT_EQ(ep.bulk_out(header(2, 8, 64, 0), std::chrono::milliseconds{50}).status, UsbStatus::ok);
  Bytes buf(80);
  const auto r = ep.bulk_in(buf, std::chrono::milliseconds{100});
  ASSERT_EQ(r.status, UsbStatus::ok);
  buf.resize(r.length);
  EXPECT_EQ(buf, cat(header(2, 8, 2, 1), "1\n", 16));
}

}  // namespace

TEST(UsbtmcWire, ExactBytesOfARequestAndAMultiTransferResponse) {
  tocd::mocks::PowerMeterTwin twin;
  std::vector<Bytes> out, in;
  usbtmc::LinkOptions lo;
  lo.max_in_transfer = 16;  // "Thorlabs,PM100USB,P0012345,1.6.0\n" (33 bytes) needs 3 transfers
  usbtmc::Link link([&] { return std::make_unique<Recorder>(twin.open_usb_endpoint(), &out, &in); }, "sim",
                    lo);
  link.open(deadline());
  link.write("*IDN?", deadline());
  EXPECT_EQ(link.read(deadline()), "Thorlabs,PM100USB,P0012345,1.6.0");

  ASSERT_EQ(out.size(), 4u);
  // DEV_DEP_MSG_OUT, bTag 1, "*IDN?\n" (6 bytes), EOM, padded 18 -> 20.
  EXPECT_EQ(out[0], cat(header(1, 1, 6, 1), "*IDN?\n", 20));
  // REQUEST_DEV_DEP_MSG_IN with bTags 2, 3, 4, each asking for 16 bytes.
  EXPECT_EQ(out[1], header(2, 2, 16, 0));
  EXPECT_EQ(out[2], header(2, 3, 16, 0));
  EXPECT_EQ(out[3], header(2, 4, 16, 0));
  ASSERT_EQ(in.size(), 3u);
  // 16 + 16 + 1 bytes; EOM only on the last; each echoes its request's bTag; padded to 4.
  EXPECT_EQ(in[0], cat(header(2, 2, 16, 0), "Thorlabs,PM100US", 28));
  EXPECT_EQ(in[1], cat(header(2, 3, 16, 0), "B,P0012345,1.6.0", 28));
  EXPECT_EQ(in[2], cat(header(2, 4, 1, 1), "\n", 16));
}

TEST(UsbtmcWire, LongMessagesSplitIntoSeveralOutTransfers) {
  tocd::mocks::PowerMeterTwin twin;
  std::vector<Bytes> out, in;
  usbtmc::LinkOptions lo;
  lo.max_out_payload = 8;
  usbtmc::Link link([&] { return std::make_unique<Recorder>(twin.open_usb_endpoint(), &out, &in); }, "sim",
                    lo);
  link.open(deadline());
  link.write("SENS:CORR:WAV 850", deadline());  // 18 bytes with '\n': 8 + 8 + 2
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0], cat(header(1, 1, 8, 0), "SENS:COR", 20));
  EXPECT_EQ(out[1], cat(header(1, 2, 8, 0), "R:WAV 85", 20));
  EXPECT_EQ(out[2], cat(header(1, 3, 2, 1), "0\n", 16));
  EXPECT_DOUBLE_EQ(twin.wavelength_nm(), 850.0);
  EXPECT_EQ(twin.stats().usb_rejected, 0);
}

TEST(UsbtmcWire, TagWrapsFrom255To1) {
  tocd::mocks::PowerMeterTwin twin;
  usbtmc::Link link(twin.usb_opener(), "sim");
  link.open(deadline());
  for (int i = 0; i < 140; ++i) {  // 2 tags per query: passes 255 once
    link.write("*OPC?", deadline());
    ASSERT_EQ(link.read(deadline()), "1");
  }
  EXPECT_EQ(link.last_tag(), 280 - 255);
  EXPECT_EQ(twin.stats().usb_rejected, 0);
}

TEST(UsbtmcWire, TheDeviceStallsOnEveryFramingDefect) {
  tocd::mocks::PowerMeterTwin twin;
  const auto ep = twin.open_usb_endpoint();
  const auto send = [&](Bytes t, const std::string& words) {
    const auto r = ep->bulk_out(t, std::chrono::milliseconds{50});
    EXPECT_EQ(r.status, UsbStatus::stall) << words;
    EXPECT_NE(r.detail.find(words), std::string::npos) << r.detail;
    EXPECT_NE(twin.stats().last_usb_rejection.find(words), std::string::npos);
    EXPECT_EQ(ep->bulk_out(cat(header(1, 9, 1, 1), "\n", 16), std::chrono::milliseconds{50}).status,
              UsbStatus::stall)
        << "a halted endpoint stays halted until CLEAR_FEATURE";
    ep->clear_halt(ep->bulk_out_address());
  };
  send(Bytes{1, 1, 0xFE, 0, 0, 0, 0, 0}, "shorter than the 12-byte header");
  send(cat(header(1, 1, 6, 1), "*IDN?\n", 18), "not padded to a multiple of 4");
  send(cat(header(3, 1, 0, 1), "", 12), "unknown MsgID 3");
  send(cat(header(1, 0, 2, 1), "x\n", 16), "bTag 0");
  Bytes inverse = cat(header(1, 5, 2, 1), "x\n", 16);
  inverse[2] = 0xFF;
  send(inverse, "not the inverse");
  send(cat(header(1, 5, 6, 1), "*IDN?\n", 24), "needs a 20-byte transfer");
  Bytes padding = cat(header(1, 5, 6, 1), "*IDN?\n", 20);
  padding[19] = 0x55;
  send(padding, "padding byte 19");
  Bytes reserved = header(2, 6, 64, 0);
  reserved[3] = 1;
  send(reserved, "reserved");
  send(header(2, 6, 64, 0x02), "TermChar");
  EXPECT_EQ(twin.stats().usb_rejected, 9);
  // After the clears, a well-formed exchange works on the same endpoint.
  expect_opc_answered(*ep);
}

// A host that never sends end-of-message cannot grow the device's memory without bound: past
// 64 KiB the message is refused with a stall, and the endpoint works again after the clear.
TEST(UsbtmcWire, AMessageWithoutEndOfMessageIsCappedAt64KiB) {
  tocd::mocks::PowerMeterTwin twin;
  const auto ep = twin.open_usb_endpoint();
  const std::string chunk(252, 'x');
  std::size_t accepted = 0;
  UsbTransfer r;
  for (int i = 0; i < 1000; ++i) {
    r = ep->bulk_out(cat(header(1, static_cast<std::uint8_t>(i % 254 + 1), 252, 0), chunk, 264),
                     std::chrono::milliseconds{50});
    if (r.status != UsbStatus::ok) break;
    accepted += chunk.size();
  }
  EXPECT_EQ(r.status, UsbStatus::stall);
  EXPECT_NE(r.detail.find("without end-of-message"), std::string::npos) << r.detail;
  EXPECT_LE(accepted, std::size_t{64 * 1024});
  EXPECT_GT(accepted + chunk.size(), std::size_t{64 * 1024});  // refused only past the cap
  ep->clear_halt(ep->bulk_out_address());
  expect_opc_answered(*ep);
}

TEST(UsbtmcWire, ControlRequestsAnswerPerTheSpec) {
  tocd::mocks::PowerMeterTwin twin;
  const auto ep = twin.open_usb_endpoint();
  std::vector<std::uint8_t> b(0x18);
  auto r = ep->control_in({0xA1, usbtmc::get_capabilities, 0, 0, 0x18}, b, std::chrono::milliseconds{50});
  ASSERT_EQ(r.status, UsbStatus::ok);
  EXPECT_EQ(r.length, 0x18u);
  EXPECT_EQ(b[0], usbtmc::status_success);
  EXPECT_EQ(b[2] | (b[3] << 8), 0x0100);  // bcdUSBTMC 1.00
  // Aborting a bulk-IN transfer that is not in progress.
  r = ep->control_in({0xA2, usbtmc::initiate_abort_bulk_in, 9, 0x81, 2}, b, std::chrono::milliseconds{50});
  EXPECT_EQ(b[0], usbtmc::status_transfer_not_in_progress);
  // Wrong recipient (interface request sent to an endpoint) stalls the control pipe.
  r = ep->control_in({0xA2, usbtmc::initiate_clear, 0, 0, 1}, b, std::chrono::milliseconds{50});
  EXPECT_EQ(r.status, UsbStatus::stall);
}

class UsbBadDevice : public pmtest::MeterOverWire {};

TEST_P(UsbBadDevice, WrongTagOrShortHeaderIsAProtocolErrorAndTheLinkRecovers) {
  twin->usb_wrong_tag(1);
  try {
    meter->measure();
    FAIL();
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("MEAS:POW?"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not echo the request's bTag"), std::string::npos) << e.what();
  }
  EXPECT_GT(meter->measure().power_W, 0.0);
  twin->usb_short_header(1);
  try {
    meter->identity();
    FAIL();
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("7 bytes is shorter than the 12-byte header"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(meter->identity().model, "PM100USB");
  EXPECT_EQ(twin->stats().usb_rejected, 0);  // the host never sent a malformed transfer
}

INSTANTIATE_TEST_SUITE_P(Usb, UsbBadDevice, testing::Values(pmtest::Wire::usb), pmtest::wire_name);
