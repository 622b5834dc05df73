#include "tocd/acquisition/protocol.hpp"

#include <cmath>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "tocd/acquisition/step_plan.hpp"
#include "tocd/core/enum_names.hpp"
#include "tocd/core/text_file.hpp"

namespace tocd::acquisition {

namespace {
constexpr std::array<EnumName<StepKind>, 3> kStepKindNames{
    {{StepKind::displacement, "displacement"}, {StepKind::strain, "strain"}, {StepKind::vacuum, "vacuum"}}};
}  // namespace

std::string_view to_string(StepKind kind) noexcept {
  return name_of(kStepKindNames, kind);
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

/// The accepted values of a protocol number: [lo, hi] (or (lo, hi] when `lo_open`), its unit
/// and why these are the limits (every error that refuses a value says so).
struct Range {
  double lo;
  double hi;
  bool lo_open;
  std::string_view unit;
  std::string_view why;
};

// The accepted range of every protocol number, with the reason for its limits.
constexpr Range kThickness{0.0, 100.0, true, "mm", "a sample under a pin; more is a unit error"};
constexpr Range kBaselinePower{0.0, 10.0, true, "W", "glass-only power on an optical power meter"};
constexpr Range kMeasureSeconds{0.0, 600.0, true, "s", "a baseline average, not a recording"};
constexpr Range kContact{0.0, 1000.0, false, "mm", "a tester position; more is a unit error"};
constexpr Range kApproach{0.0, limits::max_approach_speed_mm_per_s, true, "mm/s",
                          "the pin must not strike the tissue; above it the tester's own load limit, checked "
                          "every 1 ms, lets the load overshoot by more than the stated bound"};
constexpr Range kRetract{0.0, limits::max_retract_speed_mm_per_s, true, "mm/s",
                         "within every supported tester's speed range"};
constexpr Range kHold{0.0, 86400.0, false, "s", "at most a day; a longer wait is a unit error"};
constexpr Range kRecord{0.0, 3600.0, true, "s", "at most an hour per step; a longer window is a unit error"};
constexpr Range kTolerance{0.0, 0.5, true, "mm", "a position check looser than 0.5 mm checks nothing"};
constexpr Range kFraction{0.0, 1.0, true, "", "a fraction of the readings expected in the window"};
constexpr Range kRerecords{0.0, 10.0, false, "", "each re-recording repeats the step; more hides a fault"};
constexpr Range kSettleRate{0.0, 1000.0, true, "N/s or kPa/s", "a settle criterion, not a switch"};
constexpr Range kSettleWindow{0.0, 600.0, true, "s", "a fit window of at most 10 minutes"};
constexpr Range kSettleWait{0.0, 3600.0, false, "s", "a step waits at most an hour to settle"};
constexpr Range kTesterRate{limits::min_tester_Hz, 10000.0, false, "Hz",
                            "readings at least every 0.1 s bound the travel between two of them, and a "
                            "lost tester is noticed within the engine's fault tolerance"};
constexpr Range kOtherRate{limits::min_instrument_Hz, 10000.0, false, "Hz",
                           "a reading at least every second, so a lost instrument is noticed within the "
                           "engine's fault tolerance"};
constexpr Range kMaxLoad{0.0, limits::max_load_N, true, "N",
                         "a pin on tissue needs far less; the tester's load cell range ends near it"};
constexpr Range kVacuumLoss{0.0, 110.0, true, "kPa", "a pressure rise within the absolute range"};

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
  void only(const std::vector<std::string_view>& allowed) const {
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
    const double v = as_double(*n);
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

  /// A number within `range` (both ends checked); the error names the value, the accepted
  /// range and why the range is what it is.
  double within(std::string_view key, double fallback, const Range& range) const {
    const auto v = number(key);
    if (!v) return fallback;
    check(key, *v, range);
    return *v;
  }

  /// Checks a value already read (or derived) against `range`.
  void check(std::string_view key, double v, const Range& range) const {
    const bool low = range.lo_open ? !(v > range.lo) : !(v >= range.lo);
    if (low || !(v <= range.hi)) {
      fail(t_.get(key), key,
           fmt::format("must be {} {}, got {}; accepted: {}{}, {}] {} ({})",
                       low ? (range.lo_open ? ">" : ">=") : "<=", low ? range.lo : range.hi, v,
                       range.lo_open ? "(" : "[", range.lo, range.hi, range.unit, range.why));
    }
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

  /// Most values a list or a range may give.
  static constexpr std::size_t kMaxValues = 10000;

  /// An array of numbers, or an inline table {from, to, count} for equally spaced values.
  std::vector<double> values(std::string_view key) const {
    const auto* n = t_.get(key);
    std::vector<double> out;
    if (const auto* arr = n->as_array()) {
      // As for a {from, to, count} range: no protocol has more steps, and each one is minutes.
      if (arr->size() > kMaxValues)
        fail(n, key, fmt::format("has {} entries; at most {} are accepted", arr->size(), kMaxValues));
      for (const auto& e : *arr) {
        if (!e.is_number()) fail(&e, key, fmt::format("every entry must be a number, got {}", type_name(e)));
        out.push_back(as_double(e));
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
      if (count < 1 || count != std::floor(count) || count > static_cast<double>(kMaxValues)) {
        r.fail(range->get("count"), "count",
               fmt::format("must be a whole number in 1..{}, got {}", kMaxValues, count));
      }
      return linear_steps(from, to, static_cast<int>(count));
    }
    fail(n, key, fmt::format("must be an array of numbers or {{from, to, count}}, got {}", type_name(*n)));
  }

  const toml::table& table() const { return t_; }

 private:
  // A number node as a double. toml++ gives no double for an integer that a double cannot
  // hold exactly (beyond 2^53), and taking the empty optional ended the program (found by the
  // protocol_toml fuzz target): such an integer is read at its nearest double, and the range
  // checks that follow refuse it by value.
  static double as_double(const toml::node& n) {
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    return n.as_floating_point()->get();
  }

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

/// One number of an optional table: its key, where it lands (holding the default) and its range.
struct NumberField {
  std::string_view key;
  double* value;
  const Range* range;
};

/// One true/false of an optional table: its key and where it lands (holding the default).
struct FlagField {
  std::string_view key;
  bool* value;
};

/// Reads the optional table `name` of plain settings: only the listed keys, each number within
/// its range, each absent one left at its default. Numbers are read before flags.
void read_settings_table(const toml::table& doc, const std::string& file, std::string_view name,
                         std::initializer_list<NumberField> numbers,
                         std::initializer_list<FlagField> flags = {}) {
  const auto* t = subtable(doc, file, name, false);
  if (!t) return;
  const TableReader r(*t, file, std::string(name));
  std::vector<std::string_view> keys;
  for (const auto& f : numbers) keys.push_back(f.key);
  for (const auto& f : flags) keys.push_back(f.key);
  r.only(keys);
  for (const auto& f : numbers) *f.value = r.within(f.key, *f.value, *f.range);
  for (const auto& f : flags) *f.value = r.flag(f.key, *f.value);
}

void parse_steps(const TableReader& r, Protocol& p) {
  r.only({"displacements_mm", "strains", "vacuum_kPa", "hold_s", "record_s", "position_tolerance_mm",
          "min_sample_fraction", "max_rerecords"});
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
  p.hold_s = r.within("hold_s", p.hold_s, kHold);
  p.record_s = r.within("record_s", p.record_s, kRecord);
  p.position_tolerance_mm = r.within("position_tolerance_mm", p.position_tolerance_mm, kTolerance);
  p.min_sample_fraction = r.within("min_sample_fraction", p.min_sample_fraction, kFraction);
  const double rerecords = r.within("max_rerecords", p.max_rerecords, kRerecords);
  if (rerecords != std::floor(rerecords))
    r.fail(r.get("max_rerecords"), "max_rerecords", fmt::format("must be a whole number, got {}", rerecords));
  p.max_rerecords = static_cast<int>(rerecords);
}

/// Limits that join keys of different tables, checked once every table is read.
void check_combinations(const toml::table& doc, const std::string& file, const Protocol& p) {
  const auto reader_of = [&](std::string_view table) {
    const auto* t = doc.get(table);
    return TableReader(t && t->as_table() ? *t->as_table() : doc, file, std::string(table));
  };
  // The pin may travel at most max_travel_per_poll_mm between two readings of the tester: that
  // bounds how far past a load limit or a target it gets before the engine sees it.
  if (p.kind != StepKind::vacuum) {
    const double per_poll = p.approach_speed_mm_per_s / p.rates.tester_Hz;
    if (per_poll > limits::max_travel_per_poll_mm) {
      const bool rate_given = doc.get("rates") && doc["rates"]["tester_Hz"];
      const TableReader r = reader_of(rate_given ? "rates" : "motion");
      const std::string_view key = rate_given ? "tester_Hz" : "approach_speed_mm_per_s";
      r.fail(
          r.get(key), key,
          fmt::format("at {} mm/s and {} Hz the pin travels {:.3g} mm between two tester readings; it must "
                      "be <= {} mm so that the engine sees a load or position before the pin is past it: "
                      "raise tester_Hz to >= {:.4g} Hz or lower approach_speed_mm_per_s",
                      p.approach_speed_mm_per_s, p.rates.tester_Hz, per_poll, limits::max_travel_per_poll_mm,
                      p.approach_speed_mm_per_s / limits::max_travel_per_poll_mm));
    }
  }
  // A recording window must be long enough to hold power readings.
  if (p.record_s * p.rates.power_Hz < 1.0) {
    const TableReader r = reader_of("steps");
    r.fail(
        r.get("record_s"), "record_s",
        fmt::format("a {} s window at power_Hz = {} holds no power reading (T = mean power / baseline); it "
                    "must be >= 1 / power_Hz = {:.4g} s",
                    p.record_s, p.rates.power_Hz, 1.0 / p.rates.power_Hz));
  }
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
    r.check("thickness_mm", p.sample.thickness_mm, kThickness);
    p.sample.notes = r.text("notes");
  }
  {
    const TableReader r(*subtable(doc, source_name, "baseline", true), source_name, "baseline");
    r.only({"power_W", "measure", "measure_s"});
    p.baseline.power_W = r.number("power_W");
    p.baseline.measure = r.flag("measure", false);
    p.baseline.measure_s = r.within("measure_s", p.baseline.measure_s, kMeasureSeconds);
    if (p.baseline.power_W.has_value() == p.baseline.measure) {
      r.fail(nullptr, "power_W", "give either power_W (entered glass-only power) or measure = true");
    }
    if (p.baseline.power_W && !(*p.baseline.power_W > 0.0)) {
      r.fail(r.get("power_W"), "power_W",
             fmt::format("glass-only baseline power must be > 0 W, got {} (T = power / baseline)",
                         *p.baseline.power_W));
    }
    if (p.baseline.power_W) r.check("power_W", *p.baseline.power_W, kBaselinePower);
  }
  if (const auto* t = subtable(doc, source_name, "motion", false)) {
    const TableReader r(*t, source_name, "motion");
    r.only({"contact_position_mm", "approach_speed_mm_per_s", "retract_speed_mm_per_s", "tare_load",
            "on_move_failure"});
    p.contact_position_mm = r.within("contact_position_mm", p.contact_position_mm, kContact);
    p.approach_speed_mm_per_s = r.within("approach_speed_mm_per_s", p.approach_speed_mm_per_s, kApproach);
    p.retract_speed_mm_per_s = r.within("retract_speed_mm_per_s", p.retract_speed_mm_per_s, kRetract);
    p.tare_load = r.flag("tare_load", p.tare_load);
    const std::string on_fail = r.text("on_move_failure", "pause");
    if (on_fail != "pause" && on_fail != "interrupt") {
      r.fail(r.get("on_move_failure"), "on_move_failure",
             fmt::format("must be \"pause\" or \"interrupt\", got \"{}\"", on_fail));
    }
    p.interrupt_on_move_failure = on_fail == "interrupt";
  }
  parse_steps(TableReader(*subtable(doc, source_name, "steps", true), source_name, "steps"), p);
  read_settings_table(doc, source_name, "settle",
                      {{"max_rate", &p.settle.max_rate, &kSettleRate},
                       {"window_s", &p.settle.window_s, &kSettleWindow},
                       {"max_wait_s", &p.settle.max_wait_s, &kSettleWait}});
  read_settings_table(doc, source_name, "rates",
                      {{"tester_Hz", &p.rates.tester_Hz, &kTesterRate},
                       {"power_Hz", &p.rates.power_Hz, &kOtherRate},
                       {"pressure_Hz", &p.rates.pressure_Hz, &kOtherRate}});
  read_settings_table(doc, source_name, "interlocks",
                      {{"max_load_N", &p.interlocks.max_load_N, &kMaxLoad},
                       {"vacuum_loss_kPa", &p.interlocks.vacuum_loss_kPa, &kVacuumLoss}},
                      {{"power_over_range_pauses", &p.interlocks.power_over_range_pauses},
                       {"retract_on_trip", &p.interlocks.retract_on_trip}});
  check_combinations(doc, source_name, p);
  return p;
}

Protocol load_protocol(const std::filesystem::path& path) {
  const auto text = read_text_file(path);
  if (!text) throw ProtocolError(fmt::format("cannot read protocol file '{}'", path.string()));
  return parse_protocol(*text, path.string());
}

}  // namespace tocd::acquisition
