#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tocd/devices/scpi_link.hpp"
#include "tocd/devices/usb_endpoint.hpp"

namespace tocd::devices::usbtmc {

// USBTMC 1.0 bulk message ids and class requests (USBTMC spec tables 2, 15).
inline constexpr std::uint8_t dev_dep_msg_out = 1;
inline constexpr std::uint8_t request_dev_dep_msg_in = 2;
inline constexpr std::uint8_t dev_dep_msg_in = 2;
inline constexpr std::size_t header_size = 12;

inline constexpr std::uint8_t initiate_abort_bulk_out = 1;
inline constexpr std::uint8_t check_abort_bulk_out_status = 2;
inline constexpr std::uint8_t initiate_abort_bulk_in = 3;
inline constexpr std::uint8_t check_abort_bulk_in_status = 4;
inline constexpr std::uint8_t initiate_clear = 5;
inline constexpr std::uint8_t check_clear_status = 6;
inline constexpr std::uint8_t get_capabilities = 7;

inline constexpr std::uint8_t request_type_interface = 0xA1;  ///< IN | class | interface
inline constexpr std::uint8_t request_type_endpoint = 0xA2;   ///< IN | class | endpoint

inline constexpr std::uint8_t status_success = 0x01;
inline constexpr std::uint8_t status_pending = 0x02;
inline constexpr std::uint8_t status_failed = 0x80;
inline constexpr std::uint8_t status_transfer_not_in_progress = 0x81;

/// Next bTag after `tag`: 1..255, skipping 0.
constexpr std::uint8_t next_tag(std::uint8_t tag) noexcept {
  return tag == 255 ? 1 : static_cast<std::uint8_t>(tag + 1);
}

/// One DEV_DEP_MSG_OUT transfer: header + `payload` + zero padding to a multiple of 4.
std::vector<std::uint8_t> encode_dev_dep_msg_out(std::uint8_t tag, std::span<const std::uint8_t> payload,
                                                 bool eom);

/// One REQUEST_DEV_DEP_MSG_IN transfer (12 bytes; no TermChar).
std::array<std::uint8_t, header_size> encode_request_dev_dep_msg_in(std::uint8_t tag, std::uint32_t max_size);

/// A DEV_DEP_MSG_IN header, decoded.
struct InHeader {
  std::uint8_t tag = 0;
  std::uint32_t transfer_size = 0;
  bool eom = false;
};

/// Checks and decodes the header of a DEV_DEP_MSG_IN transfer answering request `expected_tag`
/// of at most `requested` bytes. Throws LinkError(protocol) with the exact defect (short header,
/// wrong MsgID, bTag not echoed, bad inverse, non-zero reserved bytes, oversize, truncated).
InHeader decode_dev_dep_msg_in(std::span<const std::uint8_t> transfer, std::uint8_t expected_tag,
                               std::uint32_t requested);

struct LinkOptions {
  std::uint32_t max_out_payload = 4096;  ///< bytes of message per DEV_DEP_MSG_OUT transfer
  std::uint32_t max_in_transfer = 4096;  ///< TransferSize asked for per REQUEST_DEV_DEP_MSG_IN
  std::size_t max_message = 1 << 20;     ///< a longer answer is a protocol error
  bool terminate_with_newline = true;    ///< append '\n' to program messages (Thorlabs parsers expect it)
};

/// Capabilities the device reported at open (GET_CAPABILITIES).
struct Capabilities {
  std::uint16_t bcd_usbtmc = 0;
  std::uint8_t interface_caps = 0, device_caps = 0;
};

/// ScpiLink over USBTMC bulk transfers on a UsbBulkEndpoint. At open: GET_CAPABILITIES and
/// INITIATE_CLEAR. On a bulk-OUT timeout/stall: INITIATE_ABORT_BULK_OUT (+ CLEAR_FEATURE halt);
/// on a bulk-IN timeout: INITIATE_ABORT_BULK_IN; clear(): INITIATE_CLEAR then poll
/// CHECK_CLEAR_STATUS.
class Link final : public ScpiLink {
 public:
  Link(UsbEndpointOpener opener, std::string description, LinkOptions options = {});
  ~Link() override;
  std::string describe() const override { return description_; }
  void open(Clock::time_point deadline) override;
  void close() noexcept override;
  bool is_open() const noexcept override { return endpoint_ != nullptr; }
  void write(std::string_view message, Clock::time_point deadline) override;
  std::string read(Clock::time_point deadline) override;
  void clear(Clock::time_point deadline) override;

  const Capabilities& capabilities() const noexcept { return caps_; }
  std::uint8_t last_tag() const noexcept { return tag_; }

 private:
  std::uint8_t take_tag() noexcept;
  std::vector<std::uint8_t> control(std::uint8_t type, std::uint8_t request, std::uint16_t value,
                                    std::uint16_t index, std::uint16_t length, Clock::time_point deadline);
  enum class Bulk { out, in };
  /// INITIATE_ABORT_BULK_OUT or _IN for transfer `tag`, then its CHECK_ABORT_..._STATUS while
  /// pending (USBTMC 4.2.1.2 to 4.2.1.5); after an OUT abort, CLEAR_FEATURE on the OUT halt.
  void abort_bulk(Bulk direction, std::uint8_t tag, Clock::time_point deadline) noexcept;
  [[noreturn]] void fail(LinkFailure kind, const std::string& what);

  UsbEndpointOpener opener_;
  std::string description_;
  LinkOptions options_;
  std::unique_ptr<UsbBulkEndpoint> endpoint_;
  Capabilities caps_;
  std::uint8_t tag_ = 0;  ///< last bTag used; the first transfer uses 1
};

}  // namespace tocd::devices::usbtmc
