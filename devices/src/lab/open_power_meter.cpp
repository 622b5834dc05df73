// The power-meter case of open_lab: SCPI over TCP or USBTMC, with the config's wavelength.
#include "tocd/devices/lab.hpp"
#include "tocd/devices/power_meter_drivers.hpp"

namespace tocd::devices {

std::unique_ptr<PowerMeter> open_power_meter(const PowerMeterConfig& cfg) {
  PowerMeterOptions o;
  o.timeout_s = cfg.timeout_s;
  o.retries = cfg.retries;
  std::unique_ptr<PowerMeter> meter =
      cfg.transport == PowerMeterConfig::Transport::scpi_tcp
          ? connect_scpi_tcp_power_meter(ScpiTcpAddress{cfg.host, cfg.port}, o)
          : connect_usbtmc_power_meter(UsbtmcAddress{cfg.vendor_id, cfg.product_id, cfg.serial}, o);
  if (cfg.wavelength_nm > 0.0) meter->set_wavelength_nm(cfg.wavelength_nm);
  return meter;
}

}  // namespace tocd::devices
