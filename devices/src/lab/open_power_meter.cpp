// The power-meter case of open_lab, kept apart so that the SCPI/USBTMC drivers plug in here.
#include <fmt/format.h>

#include "tocd/devices/errors.hpp"
#include "tocd/devices/lab.hpp"

namespace tocd::devices {

std::unique_ptr<PowerMeter> open_power_meter(const PowerMeterConfig& cfg) {
  const std::string name = cfg.transport == PowerMeterConfig::Transport::scpi_tcp
                               ? fmt::format("power meter {}:{}", cfg.host, cfg.port)
                               : fmt::format("power meter usb {:04x}:{:04x}", cfg.vendor_id, cfg.product_id);
  throw ConnectionError(name, "connect", "this build has no power meter driver");
}

}  // namespace tocd::devices
