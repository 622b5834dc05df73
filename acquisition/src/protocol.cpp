#include "tocd/acquisition/protocol.hpp"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "tocd/acquisition/step_plan.hpp"

namespace tocd::acquisition {

std::string_view to_string(StepKind kind) noexcept {
  switch (kind) {
    case StepKind::displacement:
      return "displacement";
    case StepKind::strain:
      return "strain";
    case StepKind::vacuum:
      return "vacuum";
  }
  return "unknown";
}

double Protocol::nominal_duration_s() const {
  double t = 0.0;
  double previous_mm = 0.0;
  for (const auto& s : steps) {
    if (kind != StepKind::vacuum && approach_speed_mm_per_s > 0.0) {
      t += std::abs(s.displacement_mm - previous_mm) / approach_speed_mm_per_s;
      previous_mm = s.displacement_mm;
    }
    t += settle.window_s + hold_s + record_s;
  }
  return t;
}

namespace {

/// Reads typed values out of one TOML table and turns every problem into a ProtocolError
/// carrying file, line and the dotted key.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string file, std::string table_name)
      : t_(table), file_(std::move(file)), name_(std::move(table_name)) {}

  [[noreturn]] void fail(const toml::node* at, std::string_view key, const std::string& what) const {
    const auto line = at ? at->source().begin.line : t_.source().begin.line;
    const std::string where = name_.empty() ? std::string(key) : fmt::format("[{}] {}", name_, key);
    throw ProtocolError(fmt::format("{}:{}: {}: {}", file_, line, where, what));
  }

  /// Rejects keys not in `allowed` (typos would otherwise silently fall back to defaults).
  void only(std::initializer_list<std::string_view> allowed) const {
    for (const auto& [k, v] : t_) {
      bool ok = false;
      for (auto a : allowed) ok = ok || k.str() == a;
      if (!ok) {
        std::string list;
        for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(&v, k.str(), fmt::format("unknown key (expected one of: {})", list));
      }
    }
  }

  const toml::node* get(std::string_view key) const { return t_.get(key); }

  std::optional<double> number(std::string_view key) const {
    const auto* n = t_.get(key);
    if (!n) return std::nullopt;
    if (!n->is_number()) fail(n, key, fmt::format("must be a number, got {}", type_name(*n)));
    const double v = n->value<double>().value();
    if (!std::isfinite(v)) fail(n, key, "must be finite");
    return v;
  }

  double number(std::string_view key, double fallback) const { return number(key).value_or(fallback); }

  double required_number(std::string_view key) const {
    if (!t_.get(key)) fail(nullptr, key, "missing (required)");
    return *number(key);
  }

  /// A number with a lower bound; `strict` excludes the bound itself.
  double bounded(std::string_view key, double fallback, double lo, bool strict) const {
    const auto v = number(key);
    if (!v) return fallback;
    if (strict ? !(*v > lo) : !(*v >= lo)) {
      fail(t_.get(key), key, fmt::format("must be {} {}, got {}", strict ? ">" : ">=", lo, *v));
    }
    return *v;
  }

  std::string text(std::string_view key, std::string fallback = {}) const {
    const auto* n = t_.get(key);
    if (!n) return fallback;
    if (!n->is_string()) fail(n, key, fmt::format("must be a string, got {}", type_name(*n)));
    return *n->value<std::string>();
  }

  bool flag(std::string_view key, bool fallback) const {
    const auto* n = t_.get(key);
    if (!n) return fallback;
    if (!n->is_boolean()) fail(n, key, fmt::format("must be true or false, got {}", type_name(*n)));
    return *n->value<bool>();
  }

  /// An array of numbers, or an inline table {from, to, count} for equally spaced values.
  std::vector<double> values(std::string_view key) const {
    const auto* n = t_.get(key);
    std::vector<double> out;
    if (const auto* arr = n->as_array()) {
      for (const auto& e : *arr) {
        if (!e.is_number()) fail(&e, key, fmt::format("every entry must be a number, got {}", type_name(e)));
        out.push_back(*e.value<double>());
      }
      if (out.empty()) fail(n, key, "needs at least one value");
      return out;
    }
    if (const auto* range = n->as_table()) {
      TableReader r(*range, file_, name_.empty() ? std::string(key) : name_ + "." + std::string(key));
      r.only({"from", "to", "count"});
      const double from = r.required_number("from");
      const double to = r.required_number("to");
      const double count = r.required_number("count");
      if (count < 1 || count != std::floor(count) || count > 10000) {
        r.fail(range->get("count"), "count",
               fmt::format("must be a whole number in 1..10000, got {}", count));
      }
      return linear_steps(from, to, static_cast<int>(count));
    }
    fail(n, key, fmt::format("must be an array of numbers or {{from, to, count}}, got {}", type_name(*n)));
  }

  const toml::table& table() const { return t_; }

 private:
  static std::string type_name(const toml::node& n) {
    std::ostringstream ss;
    ss << n.type();
    return ss.str();
  }

  const toml::table& t_;
  std::string file_;
  std::string name_;
};

const toml::table* subtable(const toml::table& doc, const std::string& file, std::string_view name,
                            bool required) {
  const auto* n = doc.get(name);
  if (!n) {
    if (required) throw ProtocolError(fmt::format("{}: missing table [{}]", file, name));
    return nullptr;
  }
  const auto* t = n->as_table();
  if (!t)
    throw ProtocolError(
        fmt::format("{}:{}: {}: must be a table [{}]", file, n->source().begin.line, name, name));
  return t;
}

void parse_steps(const TableReader& r, Protocol& p) {
  r.only({"displacements_mm", "strains", "vacuum_kPa", "hold_s", "record_s"});
  const bool has_d = r.get("displacements_mm"), has_s = r.get("strains"), has_v = r.get("vacuum_kPa");
  if (int(has_d) + int(has_s) + int(has_v) != 1) {
    r.fail(nullptr, "displacements_mm",
           "give exactly one of displacements_mm, strains (nominal strain) or vacuum_kPa");
  }
  const std::string_view key = has_d ? "displacements_mm" : has_s ? "strains" : "vacuum_kPa";
  p.kind = has_d ? StepKind::displacement : has_s ? StepKind::strain : StepKind::vacuum;
  const auto values = r.values(key);
  for (std::size_t i = 0; i < values.size(); ++i) {
    ProtocolStep s;
    s.index = static_cast<int>(i);
    s.target = values[i];
    switch (p.kind) {
      case StepKind::displacement:
        s.displacement_mm = values[i];
        s.nominal_strain = nominal_strain(values[i], p.sample.thickness_mm);
        break;
      case StepKind::strain:
        s.nominal_strain = values[i];
        s.displacement_mm = values[i] * p.sample.thickness_mm;
        break;
      case StepKind::vacuum:
        s.pressure_kPa = values[i];
        break;
    }
    if (p.kind == StepKind::vacuum
            ? !(s.pressure_kPa > 0.0 && s.pressure_kPa <= 110.0)
            : !(s.displacement_mm >= 0.0 && s.displacement_mm < p.sample.thickness_mm)) {
      r.fail(
          r.get(key), key,
          p.kind == StepKind::vacuum
              ? fmt::format("step {}: absolute pressure must lie in (0, 110] kPa, got {}", i + 1, values[i])
              : fmt::format("step {}: displacement {} mm must lie in [0, thickness {} mm)", i + 1,
                            s.displacement_mm, p.sample.thickness_mm));
    }
    p.steps.push_back(s);
  }
  p.hold_s = r.bounded("hold_s", p.hold_s, 0.0, false);
  p.record_s = r.bounded("record_s", p.record_s, 0.0, true);
}

}  // namespace

Protocol parse_protocol(std::string_view toml_text, const std::string& source_name) {
  toml::table doc;
  try {
    doc = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& src = e.source();
    throw ProtocolError(
        fmt::format("{}:{}:{}: {}", source_name, src.begin.line, src.begin.column, e.description()));
  }
  Protocol p;
  p.source_text = std::string(toml_text);
  p.source_name = source_name;
  const TableReader top(doc, source_name, "");
  top.only({"name", "sample", "baseline", "motion", "steps", "settle", "rates", "interlocks"});
  p.name = top.text("name", "unnamed protocol");

  {
    const TableReader r(*subtable(doc, source_name, "sample", true), source_name, "sample");
    r.only({"tissue", "thickness_mm", "notes"});
    p.sample.tissue = r.text("tissue");
    p.sample.thickness_mm = r.required_number("thickness_mm");
    if (!(p.sample.thickness_mm > 0.0)) {
      r.fail(r.get("thickness_mm"), "thickness_mm",
             fmt::format("must be > 0, got {}", p.sample.thickness_mm));
    }
    p.sample.notes = r.text("notes");
  }
  {
    const TableReader r(*subtable(doc, source_name, "baseline", true), source_name, "baseline");
    r.only({"power_W", "measure", "measure_s"});
    p.baseline.power_W = r.number("power_W");
    p.baseline.measure = r.flag("measure", false);
    p.baseline.measure_s = r.bounded("measure_s", p.baseline.measure_s, 0.0, true);
    if (p.baseline.power_W.has_value() == p.baseline.measure) {
      r.fail(nullptr, "power_W", "give either power_W (entered glass-only power) or measure = true");
    }
    if (p.baseline.power_W && !(*p.baseline.power_W > 0.0)) {
      r.fail(r.get("power_W"), "power_W",
             fmt::format("glass-only baseline power must be > 0 W, got {} (T = power / baseline)",
                         *p.baseline.power_W));
    }
  }
  if (const auto* t = subtable(doc, source_name, "motion", false)) {
    const TableReader r(*t, source_name, "motion");
    r.only({"contact_position_mm", "approach_speed_mm_per_s", "retract_speed_mm_per_s", "tare_load"});
    p.contact_position_mm = r.bounded("contact_position_mm", p.contact_position_mm, 0.0, false);
    p.approach_speed_mm_per_s = r.bounded("approach_speed_mm_per_s", p.approach_speed_mm_per_s, 0.0, true);
    p.retract_speed_mm_per_s = r.bounded("retract_speed_mm_per_s", p.retract_speed_mm_per_s, 0.0, true);
    p.tare_load = r.flag("tare_load", p.tare_load);
  }
  parse_steps(TableReader(*subtable(doc, source_name, "steps", true), source_name, "steps"), p);
  if (const auto* t = subtable(doc, source_name, "settle", false)) {
    const TableReader r(*t, source_name, "settle");
    r.only({"max_rate", "window_s", "max_wait_s"});
    p.settle.max_rate = r.bounded("max_rate", p.settle.max_rate, 0.0, true);
    p.settle.window_s = r.bounded("window_s", p.settle.window_s, 0.0, true);
    p.settle.max_wait_s = r.bounded("max_wait_s", p.settle.max_wait_s, 0.0, false);
  }
  if (const auto* t = subtable(doc, source_name, "rates", false)) {
    const TableReader r(*t, source_name, "rates");
    r.only({"tester_Hz", "power_Hz", "pressure_Hz"});
    p.rates.tester_Hz = r.bounded("tester_Hz", p.rates.tester_Hz, 0.0, true);
    p.rates.power_Hz = r.bounded("power_Hz", p.rates.power_Hz, 0.0, true);
    p.rates.pressure_Hz = r.bounded("pressure_Hz", p.rates.pressure_Hz, 0.0, true);
    for (const char* k : {"tester_Hz", "power_Hz", "pressure_Hz"}) {
      if (r.number(k, 1.0) > 10000.0) r.fail(r.get(k), k, "must be <= 10000 Hz");
    }
  }
  if (const auto* t = subtable(doc, source_name, "interlocks", false)) {
    const TableReader r(*t, source_name, "interlocks");
    r.only({"max_load_N", "vacuum_loss_kPa", "power_over_range_pauses", "retract_on_trip"});
    p.interlocks.max_load_N = r.bounded("max_load_N", p.interlocks.max_load_N, 0.0, true);
    p.interlocks.vacuum_loss_kPa = r.bounded("vacuum_loss_kPa", p.interlocks.vacuum_loss_kPa, 0.0, true);
    p.interlocks.power_over_range_pauses =
        r.flag("power_over_range_pauses", p.interlocks.power_over_range_pauses);
    p.interlocks.retract_on_trip = r.flag("retract_on_trip", p.interlocks.retract_on_trip);
  }
  return p;
}

Protocol load_protocol(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw ProtocolError(fmt::format("cannot read protocol file '{}'", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_protocol(ss.str(), path.string());
}

}  // namespace tocd::acquisition
