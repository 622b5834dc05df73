// The libusb side of UsbBulkEndpoint: device discovery by vendor/product id and the USBTMC
// interface's bulk pipes. Untestable without hardware; everything above it runs against the
// simulated endpoint of tocd::mocks.
#include <algorithm>
#include <mutex>

#include <fmt/format.h>
#include <libusb.h>

#include "tocd/devices/errors.hpp"
#include "tocd/devices/usb_endpoint.hpp"

namespace tocd::devices {
namespace {

UsbStatus to_status(int rc) {
  switch (rc) {
    case LIBUSB_SUCCESS:
      return UsbStatus::ok;
    case LIBUSB_ERROR_TIMEOUT:
      return UsbStatus::timeout;
    case LIBUSB_ERROR_PIPE:
      return UsbStatus::stall;
    case LIBUSB_ERROR_NO_DEVICE:
      return UsbStatus::disconnected;
    case LIBUSB_ERROR_OVERFLOW:
      return UsbStatus::overflow;
    default:
      return UsbStatus::error;
  }
}

UsbTransfer result(int rc, int transferred) {
  UsbTransfer t;
  t.status = rc < 0 ? to_status(rc) : UsbStatus::ok;
  t.length = static_cast<std::size_t>(std::max(transferred, 0));
  if (rc < 0) t.detail = libusb_strerror(static_cast<libusb_error>(rc));
  return t;
}

unsigned timeout_ms(std::chrono::milliseconds t) {
  return static_cast<unsigned>(std::max<long long>(1, t.count()));
}

/// One libusb context for the process (libusb contexts are thread-safe).
libusb_context* context(std::string* problem) {
  static std::once_flag once;
  static libusb_context* ctx = nullptr;
  static int init_rc = 0;
  std::call_once(once, [] { init_rc = libusb_init(&ctx); });
  if (init_rc != 0 && problem)
    *problem = fmt::format("libusb could not start: {}", libusb_strerror(static_cast<libusb_error>(init_rc)));
  return init_rc == 0 ? ctx : nullptr;
}

std::string read_serial(libusb_device_handle* h, const libusb_device_descriptor& d) {
  if (d.iSerialNumber == 0) return {};
  unsigned char s[256];
  const int n = libusb_get_string_descriptor_ascii(h, d.iSerialNumber, s, sizeof s);
  return n > 0 ? std::string(reinterpret_cast<char*>(s), static_cast<std::size_t>(n)) : std::string{};
}

class LibusbEndpoint final : public UsbBulkEndpoint {
 public:
  LibusbEndpoint(libusb_device_handle* h, std::uint8_t iface, std::uint8_t out, std::uint8_t in,
                 std::string desc)
      : h_(h), iface_(iface), out_(out), in_(in), desc_(std::move(desc)) {}
  ~LibusbEndpoint() override {
    libusb_release_interface(h_, iface_);
    libusb_close(h_);
  }
  std::string describe() const override { return desc_; }
  std::uint8_t interface_number() const override { return iface_; }
  std::uint8_t bulk_out_address() const override { return out_; }
  std::uint8_t bulk_in_address() const override { return in_; }
  UsbTransfer bulk_out(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    int done = 0;
    const int rc = libusb_bulk_transfer(h_, out_, const_cast<std::uint8_t*>(data.data()),
                                        static_cast<int>(data.size()), &done, timeout_ms(timeout));
    return result(rc, done);
  }
  UsbTransfer bulk_in(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override {
    int done = 0;
    const int rc = libusb_bulk_transfer(h_, in_, buffer.data(), static_cast<int>(buffer.size()), &done,
                                        timeout_ms(timeout));
    return result(rc, done);
  }
  UsbTransfer control_in(const UsbControlRequest& r, std::span<std::uint8_t> buffer,
                         std::chrono::milliseconds timeout) override {
    const int rc = libusb_control_transfer(
        h_, r.request_type, r.request, r.value, r.index, buffer.data(),
        static_cast<std::uint16_t>(std::min<std::size_t>(r.length, buffer.size())), timeout_ms(timeout));
    return result(rc < 0 ? rc : 0, rc < 0 ? 0 : rc);
  }
  UsbTransfer clear_halt(std::uint8_t address) override { return result(libusb_clear_halt(h_, address), 0); }

 private:
  libusb_device_handle* h_;
  std::uint8_t iface_, out_, in_;
  std::string desc_;
};

/// Finds the USBTMC interface (class 0xFE application specific, subclass 0x03) and its bulk pipes.
bool find_usbtmc_interface(libusb_device* dev, std::uint8_t& iface, std::uint8_t& out, std::uint8_t& in) {
  libusb_config_descriptor* cfg = nullptr;
  if (libusb_get_active_config_descriptor(dev, &cfg) != 0) return false;
  bool found = false;
  for (int i = 0; i < cfg->bNumInterfaces && !found; ++i) {
    for (int a = 0; a < cfg->interface[i].num_altsetting && !found; ++a) {
      const auto& alt = cfg->interface[i].altsetting[a];
      if (alt.bInterfaceClass != 0xFE || alt.bInterfaceSubClass != 0x03) continue;
      out = in = 0;
      for (int e = 0; e < alt.bNumEndpoints; ++e) {
        const auto& ep = alt.endpoint[e];
        if ((ep.bmAttributes & 0x03) != LIBUSB_TRANSFER_TYPE_BULK) continue;
        if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN)
          in = ep.bEndpointAddress;
        else
          out = ep.bEndpointAddress;
      }
      iface = alt.bInterfaceNumber;
      found = in != 0 && out != 0;
    }
  }
  libusb_free_config_descriptor(cfg);
  return found;
}

}  // namespace

std::string usb_meter_model(std::uint16_t vendor_id, std::uint16_t product_id) {
  if (vendor_id != thorlabs_vendor_id) return {};
  for (const auto& m : known_usb_meters)
    if (m.product_id == product_id) return m.model;
  return {};
}

UsbScan scan_usb_devices(std::uint16_t vendor_id, const std::vector<std::uint16_t>& product_ids) {
  UsbScan scan;
  libusb_context* ctx = context(&scan.problem);
  if (!ctx) return scan;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  if (n < 0) {
    scan.problem = fmt::format("cannot list USB devices: {}", libusb_strerror(static_cast<libusb_error>(n)));
    return scan;
  }
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[i], &d) != 0 || d.idVendor != vendor_id) continue;
    if (!product_ids.empty() &&
        std::find(product_ids.begin(), product_ids.end(), d.idProduct) == product_ids.end())
      continue;
    UsbDeviceInfo info;
    info.vendor_id = d.idVendor;
    info.product_id = d.idProduct;
    info.model = usb_meter_model(d.idVendor, d.idProduct);
    info.bus = libusb_get_bus_number(list[i]);
    info.address = libusb_get_device_address(list[i]);
    libusb_device_handle* h = nullptr;
    if (const int rc = libusb_open(list[i], &h); rc == 0) {
      info.serial = read_serial(h, d);
      libusb_close(h);
    } else {
      info.note = rc == LIBUSB_ERROR_ACCESS
                      ? "no permission to open (add a udev rule for this vendor id)"
                      : fmt::format("cannot open: {}", libusb_strerror(static_cast<libusb_error>(rc)));
    }
    scan.devices.push_back(std::move(info));
  }
  libusb_free_device_list(list, 1);
  return scan;
}

UsbEndpointOpener libusb_endpoint_opener(std::uint16_t vendor_id, std::uint16_t product_id,
                                         std::string serial) {
  return [vendor_id, product_id, serial]() -> std::unique_ptr<UsbBulkEndpoint> {
    const std::string who =
        fmt::format("USBTMC {:04x}:{:04x}{}{}", vendor_id, product_id, serial.empty() ? "" : " ", serial);
    std::string problem;
    libusb_context* ctx = context(&problem);
    if (!ctx) throw ConnectionError(who, "open", problem);
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    if (n < 0) throw ConnectionError(who, "open", "cannot list USB devices");
    std::unique_ptr<UsbBulkEndpoint> found;
    std::string error;
    for (ssize_t i = 0; i < n && !found; ++i) {
      libusb_device_descriptor d{};
      if (libusb_get_device_descriptor(list[i], &d) != 0 || d.idVendor != vendor_id ||
          d.idProduct != product_id)
        continue;
      libusb_device_handle* h = nullptr;
      if (const int rc = libusb_open(list[i], &h); rc != 0) {
        error = libusb_strerror(static_cast<libusb_error>(rc));
        continue;
      }
      if (!serial.empty() && read_serial(h, d) != serial) {
        libusb_close(h);
        continue;
      }
      std::uint8_t iface = 0, out = 0, in = 0;
      if (!find_usbtmc_interface(list[i], iface, out, in)) {
        error = "the device has no USBTMC interface";
        libusb_close(h);
        continue;
      }
      libusb_set_auto_detach_kernel_driver(h, 1);  // the kernel's usbtmc driver may hold it
      if (const int rc = libusb_claim_interface(h, iface); rc != 0) {
        error = fmt::format("cannot claim interface {}: {}", iface,
                            libusb_strerror(static_cast<libusb_error>(rc)));
        libusb_close(h);
        continue;
      }
      found = std::make_unique<LibusbEndpoint>(h, iface, out, in, who);
    }
    libusb_free_device_list(list, 1);
    if (!found && !error.empty()) throw ConnectionError(who, "open", error);
    return found;
  };
}

}  // namespace tocd::devices
