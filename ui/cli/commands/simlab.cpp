// `tocdlab simlab`: serves the simulated instruments on their real transports until SIGINT or
// SIGTERM (docs/instruments/simulated-lab.md).
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <unistd.h>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "sample_option.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/simulated_lab.hpp"

namespace cli = tocd::cli;

namespace {

// Self-pipe: the handler only writes a byte; the main thread sleeps in poll() on the other
// end, so SIGINT/SIGTERM end the wait at once, and the servers then stop promptly whatever
// their clients do (their threads never block on a client).
int g_signal_pipe[2] = {-1, -1};
extern "C" void on_signal(int) {
  const int saved = errno;
  const char byte = 1;
  (void)!::write(g_signal_pipe[1], &byte, 1);
  errno = saved;
}

/// Installs the handlers; the read end of the pipe becomes readable on the first signal.
int watch_stop_signals() {
  if (::pipe2(g_signal_pipe, O_CLOEXEC | O_NONBLOCK) != 0)
    throw tocd::Error(std::string("simlab: cannot create the signal pipe: ") + std::strerror(errno));
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  return g_signal_pipe[0];
}

void wait_for(int fd) {
  pollfd p{fd, POLLIN, 0};
  while (::poll(&p, 1, -1) < 0 && errno == EINTR) {
  }
}

struct SimlabOptions {
  std::string config, write_config;
  double clock_factor = 1.0, source_power_W = 1e-3, contact_mm = 1.0, thickness_mm = 2.5;
  std::uint64_t seed = 1;
  bool no_vacuum = false, no_power_meter = false;
  double max_displacement_mm = tocd::mocks::kDefaultSampleMinReachMm;
  cli::SampleChoice sample;
};

void run_simlab(const SimlabOptions& o) {
  tocd::mocks::SimulatedLabOptions opt = cli::simulated_lab_options(o.sample);
  opt.clock_factor = o.clock_factor;
  opt.source_power_W = o.source_power_W;
  opt.contact_position_mm = o.contact_mm;
  opt.seed = o.seed;
  opt.tissue = cli::prepare_sample(o.sample, o.thickness_mm, o.max_displacement_mm);
  opt.with_vacuum = !o.no_vacuum;
  opt.with_power_meter = !o.no_power_meter;
  if (!o.config.empty()) {
    // Serve on the ports a lab file names, so that file can be used as it is.
    const tocd::devices::LabConfig want = tocd::devices::load_lab_config(o.config);
    if (want.tester) opt.tester_port = want.tester->address.port;
    if (want.power_meter &&
        want.power_meter->transport == tocd::devices::PowerMeterConfig::Transport::scpi_tcp)
      opt.power_meter_port = want.power_meter->port;
    opt.with_power_meter = opt.with_power_meter && want.power_meter.has_value();
    opt.with_vacuum = opt.with_vacuum && want.vacuum.has_value();
  }
  // Before the servers start, so that a signal during start-up still stops the process.
  const int stop_signal = watch_stop_signals();
  tocd::mocks::SimulatedLab lab(opt);
  const tocd::devices::LabConfig cfg = lab.config();
  std::cout << fmt::format("simulated lab (clock factor {}, seed {}):\n", o.clock_factor, o.seed);
  std::cout << fmt::format("  mechanical tester  modbus-tcp  {}:{}\n", cfg.tester->address.host,
                           cfg.tester->address.port);
  if (cfg.power_meter)
    std::cout << fmt::format("  power meter        scpi-tcp    {}:{}\n", cfg.power_meter->host,
                             cfg.power_meter->port);
  if (cfg.vacuum)
    std::cout << fmt::format("  vacuum controller  modbus-rtu  {} (slave {})\n", cfg.vacuum->address.device,
                             cfg.vacuum->address.slave_id);
  if (!o.write_config.empty()) {
    std::ofstream out(o.write_config);
    out << tocd::devices::to_toml(cfg);
    if (!out) throw tocd::ConfigError("cannot write " + o.write_config);
    tocd::cli::announce_file("lab config", o.write_config);
  } else {
    std::cout << "\nlab config:\n" << tocd::devices::to_toml(cfg);
  }
  std::cout << "serving until interrupted (Ctrl-C or SIGTERM)" << std::endl;
  wait_for(stop_signal);
  std::cout << "stopping" << std::endl;
}

void install_simlab(CLI::App& root) {
  auto* cmd = root.add_subcommand("simlab", "Serve the simulated tester, power meter and vacuum controller");
  auto o = std::make_shared<SimlabOptions>();
  cmd->add_option("--config", o->config, "lab TOML whose tester/power-meter ports to serve on");
  cmd->add_option("--write-config", o->write_config, "write a lab TOML pointing at the simulated instruments")
      ->check(tocd::cli::output_file());
  cli::add_ranged_option(cmd, "--clock-factor", o->clock_factor, "simulated seconds per real second",
                         cli::real_above(0.0, 1e6));
  cli::add_ranged_option(cmd, "--source-power", o->source_power_W, "source power (W)",
                         cli::real_above(0.0, 1000.0));
  cli::add_ranged_option(cmd, "--contact", o->contact_mm,
                         "tester position where the pin touches the sample (mm)",
                         cli::real_in(-1000.0, 1000.0));
  cli::add_ranged_option(cmd, "--thickness", o->thickness_mm, "sample thickness (mm)",
                         cli::real_above(0.0, 100.0));
  cli::add_seed_option(*cmd, o->seed, "noise seed");
  cli::add_sample_options(*cmd, o->sample);
  cli::add_ranged_option(cmd, "--max-displacement", o->max_displacement_mm,
                         "deepest pin displacement the simulated sample is prepared for (mm; held beyond)",
                         cli::real_above(0.0, 100.0));
  cmd->add_flag("--no-vacuum", o->no_vacuum, "no vacuum controller");
  cmd->add_flag("--no-power-meter", o->no_power_meter, "no power meter");
  cmd->callback([o] { run_simlab(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(simlab, install_simlab);
