#include "tocd/sim/study/study.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "elapsed.hpp"
#include "table_builder.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/study/run_settings.hpp"

namespace tocd::sim::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

PredictionRequest base_request(const StudySettings& s) {
  PredictionRequest r;
  copy_run_settings(r, s);
  r.batches = s.batches;
  r.max_edge_mm = s.max_edge_mm;
  r.fluence_dir = s.fluence_dir;
  r.vtu_format = s.vtu_format;
  r.compressed_optics = native_skin_optics();
  r.compressed_optics.name = "compressed skin";
  return r;
}

mc::RegionOptics scaled(double a, double s, double n) {
  const auto native = native_skin_optics();
  return {native.mu_a_per_mm * a, native.mu_s_per_mm * s, native.g, native.n * n, "compressed skin"};
}

struct NamedOptics {
  const char* name;
  const char* label;
  double a, s, n;
};
// The published changes to the compressed region (model note): mu_a and mu_s to 80 / 60 %,
// n to 105 / 110 % of native skin.
constexpr NamedOptics kNamed[] = {
    {"native", "native", 1.0, 1.0, 1.0},
    {"a80", "mu_a 80%", 0.8, 1.0, 1.0},
    {"a60", "mu_a 60%", 0.6, 1.0, 1.0},
    {"s80", "mu_s 80%", 1.0, 0.8, 1.0},
    {"s60", "mu_s 60%", 1.0, 0.6, 1.0},
    {"n105", "n 105%", 1.0, 1.0, 1.05},
    {"n110", "n 110%", 1.0, 1.0, 1.10},
    {"a80s80n105", "a80 s80 n105", 0.8, 0.8, 1.05},
    {"a60s60n110", "a60 s60 n110", 0.6, 0.6, 1.10},
    {"cleared", "a60 s60 n110", 0.6, 0.6, 1.10},
};

double relative(double a, double b) {
  return b != 0.0 ? a / b : kNaN;
}
double relative_se(double a, double sa, double b, double sb) {
  if (a == 0.0 || b == 0.0) return kNaN;
  const double r = a / b;
  return std::abs(r) * std::sqrt((sa / a) * (sa / a) + (sb / b) * (sb / b));
}

nlohmann::json num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string fmt_opt(double v, const char* spec) {
  return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("-");
}

}  // namespace

void apply_optics(const std::string& name, PredictionRequest& r, std::string& label) {
  if (name == "graded") {
    r.optics_model = "graded";
    label = "graded";
    return;
  }
  r.optics_model = "threshold";
  for (const auto& n : kNamed)
    if (name == n.name) {
      r.compressed_optics = scaled(n.a, n.s, n.n);
      label = n.label;
      return;
    }
  double a = 0, s = 0, idx = 0;
  char c1 = 0, c2 = 0;
  std::istringstream in(name);
  if (in >> a >> c1 >> s >> c2 >> idx && c1 == '/' && c2 == '/' && in.peek() == EOF) {
    r.compressed_optics = {a, s, native_skin_optics().g, idx, "compressed skin"};
    mc::Optics check;
    check.regions[5] = r.compressed_optics;
    mc::validate(check, fmt::format("optics '{}'", name));
    label = fmt::format("{:g}/{:g}/{:g}", a, s, idx);
    return;
  }
  throw tocd::ConfigError(
      fmt::format("unknown optics '{}': expected native, a80, a60, s80, s60, n105, n110, a80s80n105, "
                  "a60s60n110, cleared, "
                  "graded or MU_A/MU_S/N",
                  name));
}

std::vector<StudyCase> paper_cases(const StudySettings& settings, double thickness_mm) {
  // Published displacements 0, 0.625 and 1.5 mm of a 2.5 mm slab, scaled to the thickness.
  const double scale = thickness_mm / 2.5;
  std::vector<StudyCase> cases;
  StudyCase zero{0, "glass only", base_request(settings)};
  zero.request.baseline = true;
  zero.request.thickness_mm = thickness_mm;
  cases.push_back(zero);
  const double d[3] = {0.0, 0.625 * scale, 1.5 * scale};
  for (int i = 0; i < 3; ++i) {
    StudyCase c{i + 1, "native", base_request(settings)};
    c.request.thickness_mm = thickness_mm;
    c.request.displacement_mm = d[i];
    cases.push_back(c);
  }
  const char* changes[] = {"a80", "a60", "s80", "s60", "n105", "n110", "a80s80n105", "a60s60n110"};
  int id = 4;
  for (const char* name : changes) {
    StudyCase c{id++, "", base_request(settings)};
    c.request.thickness_mm = thickness_mm;
    c.request.displacement_mm = d[2];
    apply_optics(name, c.request, c.optics_label);
    cases.push_back(c);
  }
  return cases;
}

std::vector<StudyCase> sweep_cases(const StudySettings& settings, const std::vector<double>& displacements_mm,
                                   const std::vector<double>& thicknesses_mm,
                                   const std::vector<std::string>& optics, bool with_baseline) {
  if (displacements_mm.empty()) throw tocd::ConfigError("sweep: give at least one displacement");
  const std::vector<double> hs = thicknesses_mm.empty() ? std::vector<double>{2.5} : thicknesses_mm;
  const std::vector<std::string> os = optics.empty() ? std::vector<std::string>{"native"} : optics;
  std::vector<StudyCase> cases;
  if (with_baseline) {
    StudyCase zero{0, "glass only", base_request(settings)};
    zero.request.baseline = true;
    cases.push_back(zero);
  }
  int id = 1;
  for (double h : hs)
    for (double d : displacements_mm)
      for (const auto& o : os) {
        StudyCase c{id++, "", base_request(settings)};
        c.request.thickness_mm = h;
        c.request.displacement_mm = d;
        apply_optics(o, c.request, c.optics_label);
        validate(c.request);
        cases.push_back(c);
      }
  return cases;
}

void fill_relatives(StudyTable& t) {
  auto find = [&](int id) -> const StudyRow* {
    for (const auto& r : t.rows)
      if (r.c.id == id) return &r;
    return nullptr;
  };
  const StudyRow* a = t.ref_a >= 0 ? find(t.ref_a) : nullptr;
  const StudyRow* b = t.ref_b >= 0 ? find(t.ref_b) : nullptr;
  for (auto& r : t.rows) {
    r.rel_a = a ? relative(r.p.T, a->p.T) : kNaN;
    r.rel_a_se = a ? relative_se(r.p.T, r.p.T_stderr, a->p.T, a->p.T_stderr) : kNaN;
    r.rel_b = b ? relative(r.p.T, b->p.T) : kNaN;
    r.rel_b_se = b ? relative_se(r.p.T, r.p.T_stderr, b->p.T, b->p.T_stderr) : kNaN;
    // A row against itself has no spread.
    if (a == &r) r.rel_a_se = 0.0;
    if (b == &r) r.rel_b_se = 0.0;
  }
}

TableBuilder::TableBuilder(const StudySettings& settings, int ref_a, int ref_b) {
  table_.settings = settings;
  table_.ref_a = ref_a;
  table_.ref_b = ref_b;
}

StudyRow TableBuilder::start_row(const StudyCase& c) {
  StudyRow row;
  row.c = c;
  if (!c.request.fluence_dir.empty()) row.c.request.fluence_stem = fmt::format("sim{:02d}", c.id);
  row.strain = c.request.baseline ? 0.0 : c.request.displacement_mm / c.request.thickness_mm;
  return row;
}

void TableBuilder::add(StudyRow row, const std::function<void(const StudyRow&)>& progress) {
  table_.rows.push_back(std::move(row));
  fill_relatives(table_);
  if (progress) progress(table_.rows.back());
}

StudyTable TableBuilder::finish() {
  table_.seconds = seconds_since(t0_);
  table_.fluence_series = write_fluence_series(table_);
  return std::move(table_);
}

StudyTable run_study(Predictor& predictor, const std::vector<StudyCase>& cases, const StudySettings& settings,
                     int ref_a, int ref_b, const std::function<void(const StudyRow&)>& progress) {
  TableBuilder table(settings, ref_a, ref_b);
  for (const auto& c : cases) {
    StudyRow row = TableBuilder::start_row(c);
    const auto s0 = Clock::now();
    row.p = predictor.predict(row.c.request);
    row.seconds = seconds_since(s0);
    table.add(std::move(row), progress);
  }
  return table.finish();
}

std::string table_header(int ref_a, int ref_b) {
  const std::string a = ref_a >= 0 ? fmt::format("T/T{}", ref_a) : "T/Ta";
  const std::string b = ref_b >= 0 ? fmt::format("T/T{}", ref_b) : "T/Tb";
  return fmt::format("{:>3} {:>6} {:>5} {:>6} {:<13} {:>8} {:>8} {:>7} {:>7} {:>7} {:>6} {:>6} {:>7} {:>7}\n",
                     "sim", "d_mm", "h_mm", "strain", "optics", "T", "T_se", a, b, "+-" + b, "side%",
                     "slide%", "tets", "seconds") +
         std::string(111, '-') + "\n";
}

std::string format_row(const StudyRow& r) {
  return fmt::format(
      "{:>3} {:>6.3f} {:>5.2f} {:>5.1f}% {:<13} {:>8.5f} {:>8.5f} {:>7} {:>7} {:>7} {:>6.2f} {:>6.2f} {:>7} "
      "{:>7.1f}\n",
      r.c.id, r.c.request.baseline ? 0.0 : r.c.request.displacement_mm,
      r.c.request.baseline ? 0.0 : r.c.request.thickness_mm, 100.0 * r.strain, r.c.optics_label, r.p.T,
      r.p.T_stderr, fmt_opt(r.rel_a, "{:.4f}"), fmt_opt(r.rel_b, "{:.4f}"), fmt_opt(r.rel_b_se, "{:.4f}"),
      100.0 * r.p.side_loss, 100.0 * r.p.side_loss_slide, r.p.tets, r.seconds);
}

std::string format_table(const StudyTable& t) {
  std::string out = table_header(t.ref_a, t.ref_b);
  for (const auto& r : t.rows) out += format_row(r);
  return out;
}

nlohmann::json to_json(const StudyTable& t) {
  nlohmann::json j;
  j["kind"] = "tocdlab.study";
  j["settings"] = {{"photons", t.settings.photons},         {"seed", t.settings.seed},
                   {"mesh_preset", t.settings.mesh_preset}, {"threads", t.settings.threads},
                   {"batches", t.settings.batches},         {"max_edge_mm", t.settings.max_edge_mm}};
  j["reference_a"] = t.ref_a;
  j["reference_b"] = t.ref_b;
  j["seconds"] = t.seconds;
  if (!t.fluence_series.empty()) j["fluence_series"] = t.fluence_series;
  auto& rows = j["simulations"] = nlohmann::json::array();
  for (const auto& r : t.rows) {
    nlohmann::json row = to_json(r.p);  // the prediction's own keys, then the table's
    row["sim"] = r.c.id;
    row["displacement_mm"] = r.c.request.baseline ? 0.0 : r.c.request.displacement_mm;
    row["thickness_mm"] = r.c.request.baseline ? 0.0 : r.c.request.thickness_mm;
    row["strain"] = r.strain;
    row["optics"] = r.c.optics_label;
    row["optics_model"] = r.c.request.optics_model;
    row["compressed_optics"] = to_json(r.c.request.compressed_optics);
    row["T_rel_a"] = num(r.rel_a);
    row["T_rel_a_se"] = num(r.rel_a_se);
    row["T_rel_b"] = num(r.rel_b);
    row["T_rel_b_se"] = num(r.rel_b_se);
    row["seconds"] = r.seconds;
    rows.push_back(std::move(row));
  }
  return j;
}

std::string to_csv(const StudyTable& t) {
  std::string out =
      "sim,displacement_mm,thickness_mm,strain,optics,optics_model,mu_a,mu_s,n,T,T_se,T_rel_a,T_rel_a_se,T_"
      "rel_b,"
      "T_rel_b_se,side_loss,side_loss_se,side_loss_slide,side_loss_slide_se,reflectance,absorbed,tets,"
      "seconds\n";
  auto f = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); };
  for (const auto& r : t.rows) {
    const auto& o = r.c.request.compressed_optics;
    out +=
        fmt::format("{},{},{},{},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", r.c.id,
                    f(r.c.request.baseline ? 0.0 : r.c.request.displacement_mm),
                    f(r.c.request.baseline ? 0.0 : r.c.request.thickness_mm), f(r.strain), r.c.optics_label,
                    r.c.request.optics_model, f(o.mu_a_per_mm), f(o.mu_s_per_mm), f(o.n), f(r.p.T),
                    f(r.p.T_stderr), f(r.rel_a), f(r.rel_a_se), f(r.rel_b), f(r.rel_b_se), f(r.p.side_loss),
                    f(r.p.side_loss_stderr), f(r.p.side_loss_slide), f(r.p.side_loss_slide_stderr),
                    f(r.p.reflectance), f(r.p.absorbed), r.p.tets, f(r.seconds));
  }
  return out;
}

}  // namespace tocd::sim::study
