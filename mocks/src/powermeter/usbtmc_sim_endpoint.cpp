// The simulated meter as a USBTMC device: a UsbBulkEndpoint in process that checks every
// bulk-OUT transfer byte for byte against USBTMC 1.0 and stalls on the first defect, answers
// REQUEST_DEV_DEP_MSG_IN with DEV_DEP_MSG_IN transfers (split at the requested size, EOM on
// the last), and implements the class control requests. Written apart from the host-side
// framing on purpose: the two check each other.
#include <thread>

#include <fmt/format.h>

#include "powermeter/twin_impl.hpp"

namespace tocd::mocks {
namespace {

using devices::UsbStatus;
using devices::UsbTransfer;
constexpr std::uint8_t out_ep = 0x02, in_ep = 0x81, iface = 0;
/// A command message (all transfers up to EOM) longer than this stalls the endpoint: the same
/// cap as a line over TCP (ServerLimits::max_request_bytes), so that a host that never sends
/// EOM cannot grow the meter's memory without bound.
constexpr std::size_t kMaxMessageBytes = 64 * 1024;

std::uint32_t le32(const std::uint8_t* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

class SimUsbEndpoint final : public devices::UsbBulkEndpoint {
 public:
  using Clock = PowerMeterTwin::Impl::Clock;
  explicit SimUsbEndpoint(std::shared_ptr<PowerMeterTwin::Impl> twin) : twin_(std::move(twin)) {}

  std::string describe() const override { return "simulated USBTMC power meter"; }
  std::uint8_t interface_number() const override { return iface; }
  std::uint8_t bulk_out_address() const override { return out_ep; }
  std::uint8_t bulk_in_address() const override { return in_ep; }

  UsbTransfer bulk_out(std::span<const std::uint8_t> t, std::chrono::milliseconds) override {
    if (!alive_) return {UsbStatus::disconnected, 0, "device gone"};
    if (out_halted_) return {UsbStatus::stall, 0, "bulk-OUT endpoint halted"};
    if (t.size() < 12)
      return reject(fmt::format("transfer of {} bytes is shorter than the 12-byte header", t.size()));
    if (t.size() % 4 != 0)
      return reject(fmt::format("transfer of {} bytes is not padded to a multiple of 4", t.size()));
    if (t[0] != 1 && t[0] != 2) return reject(fmt::format("unknown MsgID {}", t[0]));
    if (t[1] == 0) return reject("bTag 0 is not allowed");
    if (t[2] != static_cast<std::uint8_t>(~t[1]))
      return reject(fmt::format("bTagInverse 0x{:02X} is not the inverse of bTag 0x{:02X}", t[2], t[1]));
    if (t[3] != 0) return reject("header byte 3 (reserved) is not zero");
    const std::uint32_t size = le32(&t[4]);
    if (t[10] != 0 || t[11] != 0) return reject("header bytes 10..11 (reserved) are not zero");
    if (t[0] == 2) {  // REQUEST_DEV_DEP_MSG_IN
      if (t[8] & 0x02) return reject("TermChar requested but the device does not support it");
      if (t[8] != 0 || t[9] != 0) return reject("REQUEST_DEV_DEP_MSG_IN attribute bytes are not zero");
      if (t.size() != 12) return reject("REQUEST_DEV_DEP_MSG_IN carries data");
      if (size == 0) return reject("REQUEST_DEV_DEP_MSG_IN asks for 0 bytes");
      request_tag_ = t[1];
      request_size_ = size;
      return {UsbStatus::ok, t.size(), {}};
    }
    if ((t[8] & ~0x01) != 0 || t[9] != 0)
      return reject("DEV_DEP_MSG_OUT attribute bytes hold undefined bits");
    const std::size_t expected = (12 + static_cast<std::size_t>(size) + 3) / 4 * 4;
    if (t.size() != expected)
      return reject(
          fmt::format("TransferSize {} needs a {}-byte transfer, got {} bytes", size, expected, t.size()));
    for (std::size_t i = 12 + size; i < t.size(); ++i)
      if (t[i] != 0) return reject(fmt::format("padding byte {} is not zero", i));
    if (message_.size() + size > kMaxMessageBytes) {
      message_.clear();  // the whole message is refused, not just this transfer
      return reject(fmt::format("message longer than {} bytes without end-of-message", kMaxMessageBytes));
    }
    last_out_tag_ = t[1];
    message_.append(reinterpret_cast<const char*>(t.data() + 12), size);
    if (t[8] & 0x01) {  // EOM: the message is complete
      std::string msg = std::move(message_);
      message_.clear();
      while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
      const auto reply = twin_->handle(msg);
      if (reply.action == PowerMeterTwin::Impl::Action::drop) {
        alive_ = false;
        return {UsbStatus::disconnected, 0, "device gone"};
      }
      if (reply.action == PowerMeterTwin::Impl::Action::answer) {
        output_ = reply.bytes + "\n";
        output_ready_ = reply.ready;
      }
    }
    return {UsbStatus::ok, t.size(), {}};
  }

  UsbTransfer bulk_in(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override {
    if (!alive_) return {UsbStatus::disconnected, 0, "device gone"};
    const auto deadline = Clock::now() + timeout;
    if (request_tag_ == 0 || output_.empty()) {  // nothing asked for, or nothing to say
      std::this_thread::sleep_for(timeout);
      return {UsbStatus::timeout, 0, {}};
    }
    if (output_ready_ > deadline) {
      std::this_thread::sleep_until(deadline);
      return {UsbStatus::timeout, 0, {}};
    }
    std::this_thread::sleep_until(output_ready_);
    const std::size_t n = std::min<std::size_t>(request_size_, output_.size());
    const bool eom = n == output_.size();
    std::vector<std::uint8_t> t((12 + n + 3) / 4 * 4, 0);
    std::uint8_t tag = request_tag_;
    const auto fault = twin_->take_usb_fault();
    if (fault == PowerMeterTwin::Impl::UsbFault::wrong_tag)
      tag = static_cast<std::uint8_t>(tag == 255 ? 1 : tag + 1);
    t[0] = 2;
    t[1] = tag;
    t[2] = static_cast<std::uint8_t>(~tag);
    for (int i = 0; i < 4; ++i) t[4 + i] = static_cast<std::uint8_t>(n >> (8 * i));
    t[8] = eom ? 1 : 0;
    std::copy(output_.begin(), output_.begin() + static_cast<std::ptrdiff_t>(n), t.begin() + 12);
    if (fault == PowerMeterTwin::Impl::UsbFault::short_header) t.resize(7);
    if (buffer.size() < t.size()) return {UsbStatus::overflow, 0, "host buffer smaller than the transfer"};
    std::copy(t.begin(), t.end(), buffer.begin());
    output_.erase(0, n);
    request_tag_ = 0;
    return {UsbStatus::ok, t.size(), {}};
  }

  UsbTransfer control_in(const devices::UsbControlRequest& r, std::span<std::uint8_t> buffer,
                         std::chrono::milliseconds) override {
    if (!alive_) return {UsbStatus::disconnected, 0, "device gone"};
    std::vector<std::uint8_t> reply;
    const bool to_endpoint = r.request >= 1 && r.request <= 4;
    const std::uint8_t want_type = to_endpoint ? 0xA2 : 0xA1;
    const std::uint16_t want_index = r.request <= 2 ? out_ep : r.request <= 4 ? in_ep : iface;
    static constexpr std::uint16_t lengths[] = {0, 2, 8, 2, 8, 1, 2, 0x18};
    if (r.request < 1 || r.request > 7 || r.request_type != want_type || r.index != want_index ||
        r.length != lengths[r.request])
      return {UsbStatus::stall, 0, fmt::format("control request {} malformed", r.request)};
    const auto tag = static_cast<std::uint8_t>(r.value & 0xFF);
    // An abort names the transfer by its bTag: STATUS_SUCCESS and its data dropped when that
    // transfer is the one in progress, STATUS_TRANSFER_NOT_IN_PROGRESS otherwise.
    const auto abort_reply = [tag](bool in_progress) {
      return std::vector<std::uint8_t>{static_cast<std::uint8_t>(in_progress ? 0x01 : 0x81), tag};
    };
    switch (r.request) {
      case 1: {  // INITIATE_ABORT_BULK_OUT
        const bool in_progress = tag == last_out_tag_ && tag != 0;
        if (in_progress) message_.clear();
        reply = abort_reply(in_progress);
        break;
      }
      case 3: {  // INITIATE_ABORT_BULK_IN
        const bool in_progress = request_tag_ != 0 && tag == request_tag_;
        if (in_progress) {
          request_tag_ = 0;
          output_.clear();
        }
        reply = abort_reply(in_progress);
        break;
      }
      case 2:  // CHECK_ABORT_BULK_OUT_STATUS
      case 4:  // CHECK_ABORT_BULK_IN_STATUS: both aborts finish at once
        reply = {0x01, 0, 0, 0, 0, 0, 0, 0};
        break;
      case 5:  // INITIATE_CLEAR
        message_.clear();
        output_.clear();
        request_tag_ = 0;
        reply = {0x01};
        break;
      case 6:
        reply = {0x01, 0};
        break;  // CHECK_CLEAR_STATUS
      case 7:   // GET_CAPABILITIES: USBTMC 1.00, no TermChar, not USB488
        reply.assign(0x18, 0);
        reply[0] = 0x01;
        reply[2] = 0x00;
        reply[3] = 0x01;
        break;
    }
    const std::size_t n = std::min(reply.size(), buffer.size());
    std::copy_n(reply.begin(), n, buffer.begin());
    return {UsbStatus::ok, n, {}};
  }

  UsbTransfer clear_halt(std::uint8_t address) override {
    if (!alive_) return {UsbStatus::disconnected, 0, "device gone"};
    if (address == out_ep) out_halted_ = false;
    return {UsbStatus::ok, 0, {}};
  }

 private:
  UsbTransfer reject(const std::string& why) {
    out_halted_ = true;  // a USBTMC device halts bulk-OUT on a transfer it cannot parse
    twin_->note_usb_rejection(why);
    return {UsbStatus::stall, 0, why};
  }

  std::shared_ptr<PowerMeterTwin::Impl> twin_;
  bool alive_ = true;
  bool out_halted_ = false;
  std::string message_;  ///< DEV_DEP_MSG_OUT payload so far (until EOM)
  std::uint8_t last_out_tag_ = 0;
  std::uint8_t request_tag_ = 0;  ///< outstanding REQUEST_DEV_DEP_MSG_IN, 0 = none
  std::uint32_t request_size_ = 0;
  std::string output_;  ///< answer bytes not yet sent
  Clock::time_point output_ready_{};
};

}  // namespace

namespace {
std::unique_ptr<devices::UsbBulkEndpoint> plug_in(const std::shared_ptr<PowerMeterTwin::Impl>& impl) {
  {
    std::lock_guard lock(impl->mutex);
    if (impl->usb_unplugged) return nullptr;
    ++impl->stats.usb_opens;
  }
  return std::make_unique<SimUsbEndpoint>(impl);
}
}  // namespace

std::unique_ptr<devices::UsbBulkEndpoint> PowerMeterTwin::open_usb_endpoint() {
  return plug_in(impl_);
}

devices::UsbEndpointOpener PowerMeterTwin::usb_opener() {
  // Holds the meter weakly: an opener kept after the twin is gone finds no device.
  std::weak_ptr<Impl> weak = impl_;
  return [weak]() -> std::unique_ptr<devices::UsbBulkEndpoint> {
    const auto impl = weak.lock();
    return impl ? plug_in(impl) : nullptr;
  };
}

}  // namespace tocd::mocks
