// ScpiLink over USBTMC bulk transfers. The framing lives in usbtmc_framing.cpp; this file is
// the message loop (split OUT messages, read IN transfers until EOM) and the recovery
// sequences of USBTMC 1.0 section 4.2.1 (abort bulk-OUT / bulk-IN, clear).
#include <thread>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/devices/usbtmc.hpp"
#include "trace.hpp"

namespace tocd::devices::usbtmc {
namespace {

std::chrono::milliseconds left(Clock::time_point deadline) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  return std::max(ms, std::chrono::milliseconds{1});
}

/// Control requests get their own short budget: they run after a bulk wait already used up
/// the caller's deadline.
constexpr std::chrono::milliseconds control_timeout{250};
constexpr int status_polls = 20;

const char* status_name(UsbStatus s) {
  switch (s) {
    case UsbStatus::ok:
      return "ok";
    case UsbStatus::timeout:
      return "timed out";
    case UsbStatus::stall:
      return "endpoint stalled";
    case UsbStatus::disconnected:
      return "device disconnected";
    case UsbStatus::overflow:
      return "overflow";
    case UsbStatus::error:
      return "I/O error";
  }
  return "?";
}

}  // namespace

Link::Link(UsbEndpointOpener opener, std::string description, LinkOptions options)
    : opener_(std::move(opener)), description_(std::move(description)), options_(options) {
  if (!opener_) throw tocd::ConfigError(description_ + ": no USB endpoint opener");
  if (options_.max_out_payload == 0 || options_.max_in_transfer == 0)
    throw tocd::ConfigError(description_ + ": USBTMC transfer sizes must be positive");
}

Link::~Link() {
  close();
}

std::uint8_t Link::take_tag() noexcept {
  return tag_ = next_tag(tag_);
}

void Link::fail(LinkFailure kind, const std::string& what) {
  if (kind == LinkFailure::disconnected) endpoint_.reset();
  throw LinkError(kind, what);
}

void Link::open(Clock::time_point deadline) {
  close();
  std::unique_ptr<UsbBulkEndpoint> ep;
  try {
    ep = opener_();
  } catch (const std::exception& e) {
    throw LinkError(LinkFailure::disconnected, e.what());
  }
  if (!ep) throw LinkError(LinkFailure::disconnected, "device not found on the USB bus");
  endpoint_ = std::move(ep);
  const auto caps =
      control(request_type_interface, get_capabilities, 0, endpoint_->interface_number(), 0x18, deadline);
  if (caps.size() < 6 || caps[0] != status_success)
    fail(LinkFailure::protocol,
         fmt::format("GET_CAPABILITIES failed (status 0x{:02X})", caps.empty() ? 0 : caps[0]));
  caps_.bcd_usbtmc = static_cast<std::uint16_t>(caps[2] | (caps[3] << 8));
  caps_.interface_caps = caps[4];
  caps_.device_caps = caps[5];
  clear(deadline);  // start from empty buffers whatever the last owner left behind
}

void Link::close() noexcept {
  endpoint_.reset();
}

std::vector<std::uint8_t> Link::control(std::uint8_t type, std::uint8_t request, std::uint16_t value,
                                        std::uint16_t index, std::uint16_t length,
                                        Clock::time_point deadline) {
  if (!endpoint_) fail(LinkFailure::disconnected, "not connected");
  std::vector<std::uint8_t> buf(length);
  const auto timeout = std::max(control_timeout, left(deadline));
  const UsbTransfer r = endpoint_->control_in({type, request, value, index, length}, buf, timeout);
  if (r.status == UsbStatus::disconnected) fail(LinkFailure::disconnected, "device disconnected");
  if (r.status == UsbStatus::timeout)
    fail(LinkFailure::timeout, fmt::format("control request {} timed out", request));
  if (r.status != UsbStatus::ok)
    fail(LinkFailure::protocol,
         fmt::format("control request {}: {} {}", request, status_name(r.status), r.detail));
  buf.resize(r.length);
  return buf;
}

void Link::abort_bulk(Bulk direction, std::uint8_t tag, Clock::time_point deadline) noexcept {
  const bool out = direction == Bulk::out;
  try {
    const auto ep = out ? endpoint_->bulk_out_address() : endpoint_->bulk_in_address();
    const auto st = control(request_type_endpoint, out ? initiate_abort_bulk_out : initiate_abort_bulk_in,
                            tag, ep, 2, deadline);
    if (!st.empty() && st[0] == status_success) {
      const auto check = out ? check_abort_bulk_out_status : check_abort_bulk_in_status;
      for (int i = 0; i < status_polls; ++i) {
        const auto c = control(request_type_endpoint, check, 0, ep, 8, deadline);
        if (c.empty() || c[0] != status_pending) break;
        std::this_thread::sleep_for(std::chrono::milliseconds{5});
      }
    }
    if (out) endpoint_->clear_halt(ep);  // USBTMC 4.2.1.3: the host clears the bulk-OUT halt
  } catch (const LinkError&) {
    // Recovery is best effort: the caller reports the original failure, and clear() or a
    // reconnect follows.
  }
}

void Link::write(std::string_view message, Clock::time_point deadline) {
  if (!endpoint_) fail(LinkFailure::disconnected, "not connected");
  std::string text(message);
  if (options_.terminate_with_newline) text += '\n';
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(text.data());
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(options_.max_out_payload, text.size() - pos);
    const bool eom = pos + n == text.size();
    const std::uint8_t tag = take_tag();
    const auto transfer = encode_dev_dep_msg_out(tag, {bytes + pos, n}, eom);
    if (trace_enabled())
      trace_log().trace("{}: usbtmc bulk-OUT DEV_DEP_MSG_OUT bTag {}: {}", description_, tag,
                        hex_bytes(transfer));
    const UsbTransfer r = endpoint_->bulk_out(transfer, left(deadline));
    if (r.status == UsbStatus::disconnected) fail(LinkFailure::disconnected, "device disconnected");
    if (r.status != UsbStatus::ok || r.length != transfer.size()) {
      abort_bulk(Bulk::out, tag, deadline);
      if (r.status == UsbStatus::timeout) fail(LinkFailure::timeout, "bulk-OUT transfer timed out");
      fail(LinkFailure::protocol,
           fmt::format("bulk-OUT transfer (bTag {}) refused: {} {}", tag, status_name(r.status), r.detail));
    }
    pos += n;
  } while (pos < text.size());
}

std::string Link::read(Clock::time_point deadline) {
  if (!endpoint_) fail(LinkFailure::disconnected, "not connected");
  std::string message;
  std::vector<std::uint8_t> buf(header_size + options_.max_in_transfer + 3);
  for (;;) {
    const std::uint8_t tag = take_tag();
    const auto request = encode_request_dev_dep_msg_in(tag, options_.max_in_transfer);
    if (trace_enabled())
      trace_log().trace("{}: usbtmc bulk-OUT REQUEST_DEV_DEP_MSG_IN bTag {}: {}", description_, tag,
                        hex_bytes(request));
    const UsbTransfer w = endpoint_->bulk_out(request, left(deadline));
    if (w.status == UsbStatus::disconnected) fail(LinkFailure::disconnected, "device disconnected");
    if (w.status != UsbStatus::ok) {
      abort_bulk(Bulk::out, tag, deadline);
      fail(w.status == UsbStatus::timeout ? LinkFailure::timeout : LinkFailure::protocol,
           fmt::format("REQUEST_DEV_DEP_MSG_IN (bTag {}): {}", tag, status_name(w.status)));
    }
    const UsbTransfer r = endpoint_->bulk_in(buf, left(deadline));
    if (r.status == UsbStatus::disconnected) fail(LinkFailure::disconnected, "device disconnected");
    if (r.status == UsbStatus::timeout) {
      abort_bulk(Bulk::in, tag, deadline);
      fail(LinkFailure::timeout, message.empty() ? "no answer" : "answer incomplete (no EOM)");
    }
    if (r.status != UsbStatus::ok) {
      abort_bulk(Bulk::in, tag, deadline);
      fail(LinkFailure::protocol, fmt::format("bulk-IN transfer: {} {}", status_name(r.status), r.detail));
    }
    const std::span<const std::uint8_t> transfer(buf.data(), r.length);
    if (trace_enabled())
      trace_log().trace("{}: usbtmc bulk-IN bTag {}: {}", description_, tag, hex_bytes(transfer));
    const InHeader h = decode_dev_dep_msg_in(transfer, tag, options_.max_in_transfer);
    message.append(reinterpret_cast<const char*>(transfer.data() + header_size), h.transfer_size);
    if (message.size() > options_.max_message)
      fail(LinkFailure::protocol, fmt::format("answer longer than {} bytes", options_.max_message));
    if (h.eom) break;
    if (Clock::now() >= deadline)
      fail(LinkFailure::timeout, "answer incomplete (no EOM before the deadline)");
  }
  while (!message.empty() && (message.back() == '\n' || message.back() == '\r')) message.pop_back();
  return message;
}

void Link::clear(Clock::time_point deadline) {
  if (!endpoint_) fail(LinkFailure::disconnected, "not connected");
  const auto st =
      control(request_type_interface, initiate_clear, 0, endpoint_->interface_number(), 1, deadline);
  if (st.empty() || st[0] != status_success)
    fail(LinkFailure::protocol,
         fmt::format("INITIATE_CLEAR failed (status 0x{:02X})", st.empty() ? 0 : st[0]));
  for (int i = 0;; ++i) {
    const auto c =
        control(request_type_interface, check_clear_status, 0, endpoint_->interface_number(), 2, deadline);
    if (c.empty() || c[0] != status_pending) break;
    if (i == status_polls) fail(LinkFailure::timeout, "CHECK_CLEAR_STATUS still pending");
    std::this_thread::sleep_for(std::chrono::milliseconds{5});
  }
  endpoint_->clear_halt(endpoint_->bulk_out_address());  // USBTMC 4.2.1.6: host clears the OUT halt
}

}  // namespace tocd::devices::usbtmc
