#include <fmt/format.h>

#include "tocd/devices/lab.hpp"
#include "tocd/devices/tester_driver.hpp"
#include "tocd/devices/vacuum_driver.hpp"

namespace tocd::devices {

LabInstruments open_lab(const LabConfig& cfg) {
  LabInstruments lab;  // on a throw, what was opened closes again with it
  if (cfg.tester) lab.tester = connect_modbus_tcp_tester(cfg.tester->address, cfg.tester->link);
  if (cfg.power_meter) lab.power_meter = open_power_meter(*cfg.power_meter);
  if (cfg.vacuum) lab.vacuum = connect_modbus_rtu_vacuum(cfg.vacuum->address, cfg.vacuum->link);
  return lab;
}

}  // namespace tocd::devices
