#pragma once

// Acquisition protocols (docs/protocol.md) as TOML text, written in one place for every test
// that runs one: each test says only what its run needs to differ in.

#include <optional>
#include <string>

#include <fmt/format.h>

namespace tocd::test {

/// The `[settle]` table: when a step's reading counts as settled.
struct SettleText {
  double max_rate = 0.05;
  double window_s = 0.5;
  double max_wait_s = 5.0;
};

/// A pin-compression protocol. Optional fields are left out of the text when empty, so the
/// protocol's own defaults apply.
struct PinProtocolText {
  std::string name = "test";
  std::string tissue = "skin";
  double thickness_mm = 2.5;
  double contact_position_mm = 1.0;
  double approach_speed_mm_per_s = 1.0;
  std::optional<double> retract_speed_mm_per_s;
  std::string displacements_mm = "0.5";  ///< the TOML array's contents, e.g. "0.25, 0.5"
  std::optional<double> hold_s = 0.5;
  double record_s = 1.0;
  std::optional<SettleText> settle = SettleText{};
  double tester_Hz = 200.0;
  std::optional<double> power_Hz;
  std::optional<double> pressure_Hz;
  std::optional<double> max_load_N;  ///< `[interlocks] max_load_N`
};

/// A vacuum protocol (no pin motion).
struct VacuumProtocolText {
  std::string name = "vacuum test";
  std::string tissue = "skin";
  double thickness_mm = 2.0;
  std::string vacuum_kPa = "10";  ///< the TOML array's contents
  double hold_s = 0.5;
  double record_s = 1.0;
  SettleText settle{0.5, 0.5, 10.0};
  std::optional<double> tester_Hz;  ///< a tester beside the pump, polled but not driven
  double power_Hz = 10.0;
  double pressure_Hz = 20.0;
  std::optional<double> vacuum_loss_kPa = 5.0;  ///< `[interlocks] vacuum_loss_kPa`
};

namespace detail {
inline std::string optional_line(const char* key, const std::optional<double>& v) {
  return v ? fmt::format("{} = {}\n", key, *v) : std::string{};
}
inline std::string settle_table(const SettleText& s) {
  return fmt::format("[settle]\nmax_rate = {}\nwindow_s = {}\nmax_wait_s = {}\n", s.max_rate, s.window_s,
                     s.max_wait_s);
}
}  // namespace detail

inline std::string protocol_toml(const PinProtocolText& p) {
  std::string t = fmt::format(
      "name = \"{}\"\n[sample]\ntissue = \"{}\"\nthickness_mm = {}\n[baseline]\npower_W = 1.0e-3\n"
      "[motion]\ncontact_position_mm = {}\napproach_speed_mm_per_s = {}\n",
      p.name, p.tissue, p.thickness_mm, p.contact_position_mm, p.approach_speed_mm_per_s);
  t += detail::optional_line("retract_speed_mm_per_s", p.retract_speed_mm_per_s);
  t += fmt::format("[steps]\ndisplacements_mm = [{}]\n", p.displacements_mm);
  t += detail::optional_line("hold_s", p.hold_s);
  t += fmt::format("record_s = {}\n", p.record_s);
  if (p.settle) t += detail::settle_table(*p.settle);
  t += fmt::format("[rates]\ntester_Hz = {}\n", p.tester_Hz);
  t += detail::optional_line("power_Hz", p.power_Hz);
  t += detail::optional_line("pressure_Hz", p.pressure_Hz);
  if (p.max_load_N) t += fmt::format("[interlocks]\nmax_load_N = {}\n", *p.max_load_N);
  return t;
}

inline std::string protocol_toml(const VacuumProtocolText& p) {
  std::string t = fmt::format(
      "name = \"{}\"\n[sample]\ntissue = \"{}\"\nthickness_mm = {}\n[baseline]\npower_W = 1.0e-3\n"
      "[steps]\nvacuum_kPa = [{}]\nhold_s = {}\nrecord_s = {}\n",
      p.name, p.tissue, p.thickness_mm, p.vacuum_kPa, p.hold_s, p.record_s);
  t += detail::settle_table(p.settle);
  t += "[rates]\n" + detail::optional_line("tester_Hz", p.tester_Hz);
  t += fmt::format("power_Hz = {}\npressure_Hz = {}\n", p.power_Hz, p.pressure_Hz);
  if (p.vacuum_loss_kPa) t += fmt::format("[interlocks]\nvacuum_loss_kPa = {}\n", *p.vacuum_loss_kPa);
  return t;
}

}  // namespace tocd::test
