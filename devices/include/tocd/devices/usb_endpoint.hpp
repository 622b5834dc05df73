#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace tocd::devices {

/// Outcome of one USB transfer, as libusb reports it.
enum class UsbStatus { ok, timeout, stall, disconnected, overflow, error };

struct UsbTransfer {
  UsbStatus status = UsbStatus::ok;
  std::size_t length = 0;  ///< bytes moved (also on timeout: a partial transfer)
  std::string detail;      ///< library text when status != ok
};

/// A class-specific control request with a device-to-host data stage (all USBTMC requests).
struct UsbControlRequest {
  std::uint8_t request_type = 0;  ///< bmRequestType, e.g. 0xA1 (class, interface, IN)
  std::uint8_t request = 0;       ///< bRequest
  std::uint16_t value = 0;        ///< wValue
  std::uint16_t index = 0;        ///< wIndex (interface number or endpoint address)
  std::uint16_t length = 0;       ///< wLength
};

/// The bulk-OUT / bulk-IN pair and control pipe of one USBTMC interface. Implemented once over
/// libusb and once by the in-process simulated meter (tocd::mocks), so the same USBTMC framing
/// code runs against both. Calls never block longer than their timeout. Not thread-safe.
class UsbBulkEndpoint {
 public:
  virtual ~UsbBulkEndpoint() = default;
  virtual std::string describe() const = 0;
  virtual std::uint8_t interface_number() const = 0;
  virtual std::uint8_t bulk_out_address() const = 0;  ///< e.g. 0x02
  virtual std::uint8_t bulk_in_address() const = 0;   ///< e.g. 0x81
  virtual UsbTransfer bulk_out(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) = 0;
  /// Reads one transfer (ends at a short packet or when `buffer` is full).
  virtual UsbTransfer bulk_in(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) = 0;
  virtual UsbTransfer control_in(const UsbControlRequest& request, std::span<std::uint8_t> buffer,
                                 std::chrono::milliseconds timeout) = 0;
  /// CLEAR_FEATURE(ENDPOINT_HALT) on the bulk endpoint `address`.
  virtual UsbTransfer clear_halt(std::uint8_t address) = 0;
};

/// Opens (again) the endpoint of one device; called at connect and after the device vanished.
/// Returns null when the device is not there (the caller retries with backoff).
using UsbEndpointOpener = std::function<std::unique_ptr<UsbBulkEndpoint>()>;

/// Thorlabs-class power meters: vendor 0x1313 and the product ids tocdlab knows.
inline constexpr std::uint16_t thorlabs_vendor_id = 0x1313;
struct KnownUsbMeter {
  std::uint16_t product_id;
  const char* model;
};
inline constexpr KnownUsbMeter known_usb_meters[] = {
    {0x8078, "PM100D"}, {0x8072, "PM100USB"}, {0x807D, "PM400"}};
/// Model name of a known product id, or "" if unknown.
std::string usb_meter_model(std::uint16_t vendor_id, std::uint16_t product_id);

/// One USB device found by a scan.
struct UsbDeviceInfo {
  std::uint16_t vendor_id = 0, product_id = 0;
  std::string model;  ///< from known_usb_meters
  int bus = 0, address = 0;
  std::string serial;  ///< empty when it could not be read
  std::string note;    ///< e.g. "no permission to open (udev rule?)"
};

struct UsbScan {
  std::vector<UsbDeviceInfo> devices;
  std::string problem;  ///< non-empty when USB could not be scanned at all (no libusb context)
};

/// Lists attached devices with `vendor_id` and one of `product_ids` (all products if empty).
/// Never throws for a missing bus or missing permissions: it says so in `problem`/`note`.
UsbScan scan_usb_devices(std::uint16_t vendor_id, const std::vector<std::uint16_t>& product_ids);

/// Opener for the first device matching vendor, product and (if non-empty) serial, through
/// libusb: finds the USBTMC interface (class 0xFE, subclass 0x03), detaches a kernel driver,
/// claims it. The opener returns null when no such device is attached, and throws
/// ConnectionError when one is attached but cannot be opened (permissions, busy).
UsbEndpointOpener libusb_endpoint_opener(std::uint16_t vendor_id, std::uint16_t product_id,
                                         std::string serial);

}  // namespace tocd::devices
