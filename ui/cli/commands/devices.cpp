// `tocdlab devices probe --lab lab.toml`: identity and one reading of every instrument.
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "output_naming.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/lab.hpp"

namespace {

struct ProbeOptions {
  std::string lab;
  bool json = false;
};

nlohmann::json identity_json(const tocd::devices::Identity& id) {
  return {{"vendor", id.vendor}, {"model", id.model}, {"serial", id.serial}, {"firmware", id.firmware}};
}

/// Probes one instrument; a failure is reported for it and the others are still probed.
template <class F>
bool probe(const char* name, nlohmann::json& out, F&& f) {
  try {
    out[name] = f();
    return true;
  } catch (const tocd::Error& e) {
    out[name] = {{"error", e.what()}};
    return false;
  }
}

void run_probe(const ProbeOptions& o) {
  namespace d = tocd::devices;
  const d::LabConfig cfg = d::load_lab_config(o.lab);
  nlohmann::json out = nlohmann::json::object();
  bool ok = true;
  if (cfg.tester)
    ok &= probe("tester", out, [&] {
      d::LabConfig one;
      one.tester = cfg.tester;
      auto t = d::open_lab(one).tester;
      const auto r = t->read();
      return nlohmann::json{{"identity", identity_json(t->identity())},
                            {"position_mm", r.position_mm},
                            {"load_N", r.load_N},
                            {"ready", r.status.ready},
                            {"fault_code", r.status.fault_code}};
    });
  if (cfg.power_meter)
    ok &= probe("power_meter", out, [&] {
      auto m = d::open_power_meter(*cfg.power_meter);
      const auto r = m->measure();
      return nlohmann::json{{"identity", identity_json(m->identity())},
                            {"sensor", m->sensor_identity()},
                            {"power_W", r.power_W},
                            {"over_range", r.over_range}};
    });
  if (cfg.vacuum)
    ok &= probe("vacuum", out, [&] {
      d::LabConfig one;
      one.vacuum = cfg.vacuum;
      auto v = d::open_lab(one).vacuum;
      const auto r = v->read();
      return nlohmann::json{{"identity", identity_json(v->identity())},
                            {"pressure_kPa", r.pressure_kPa},
                            {"setpoint_kPa", r.setpoint_kPa},
                            {"pump_running", r.pump_running},
                            {"error_code", r.error_code}};
    });
  if (o.json) {
    tocd::cli::print_json(out);
  } else {
    for (const auto& [name, v] : out.items()) {
      if (v.contains("error")) {
        std::cout << fmt::format("{:<12} FAILED: {}\n", name, v["error"].get<std::string>());
        continue;
      }
      const auto& id = v["identity"];
      std::cout << fmt::format("{:<12} {} {} (serial {}, firmware {})\n", name,
                               id["vendor"].get<std::string>(), id["model"].get<std::string>(),
                               id["serial"].get<std::string>(), id["firmware"].get<std::string>());
      for (const auto& [k, x] : v.items())
        if (k != "identity") std::cout << fmt::format("{:<12}   {} = {}\n", "", k, x.dump());
    }
  }
  if (!ok) throw tocd::Error("at least one instrument could not be probed");
}

void install_devices(CLI::App& root) {
  auto* cmd = root.add_subcommand("devices", "Instrument tools");
  cmd->require_subcommand(1);
  auto* probe_cmd =
      cmd->add_subcommand("probe", "Connect to each instrument of a lab config: identity, one reading");
  auto o = std::make_shared<ProbeOptions>();
  probe_cmd->add_option("--lab", o->lab, "lab TOML")->required();
  probe_cmd->add_flag("--json", o->json, "machine-readable output");
  probe_cmd->callback([o] { run_probe(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(devices, install_devices);
