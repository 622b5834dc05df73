#include "backend_db.hpp"

#include <QFileInfo>
#include <cmath>
#include <fstream>

#include "background.hpp"
#include "qt_text.hpp"
#include "tocd/analysis/fitted_comparison.hpp"
#include "tocd/db/export.hpp"
#include "tocd/db/location.hpp"

namespace tocd::gui {

namespace {

QDateTime utc_of(std::int64_t epoch_ns) {
  return QDateTime::fromMSecsSinceEpoch(epoch_ns / 1000000, Qt::UTC);
}

const db::Channel* find_channel(const std::vector<db::Channel>& channels, const std::string& name,
                                const std::string& fallback_unit) {
  for (const auto& c : channels)
    if (c.name == name) return &c;
  for (const auto& c : channels)
    if (c.unit == fallback_unit) return &c;
  return nullptr;
}

}  // namespace

std::vector<StepRow> step_rows(const std::vector<db::CompareRow>& compare,
                               const std::vector<db::Channel>& channels) {
  const db::Channel* load = find_channel(channels, "load", "N");
  std::vector<StepRow> rows;
  rows.reserve(compare.size());
  for (const db::CompareRow& c : compare) {
    StepRow r;
    r.step = c.step.index;
    r.displacement_mm = c.step.target_displacement_mm;
    r.nominal_strain = c.step.nominal_strain;
    r.measured_T = c.step.measured_transmission;
    const db::ChannelStats* st = load ? c.step.stats_for(load->id) : nullptr;
    r.load_N = st ? st->mean : std::nan("");
    if (c.prediction) {
      r.predicted_T = c.prediction->T;
      r.predicted_T_stderr = c.prediction->T_stderr;
      if (!std::isnan(c.prediction->latency_s)) r.prediction_latency_s = c.prediction->latency_s;
    }
    rows.push_back(r);
  }
  return rows;
}

RunListing listing_of(const db::RunSummary& s) {
  RunListing l;
  l.id = s.run.id;
  l.uuid = qs(s.run.uuid);
  l.name = qs(s.run.name);
  l.status = QString::fromLatin1(db::to_string(db::shown_status(s)).data());
  l.operator_name = qs(s.run.operator_name);
  l.started_utc = utc_of(s.run.started_utc_ns);
  l.steps = s.steps;
  l.predictions = s.predictions;
  l.events = s.events;
  l.live = s.live;
  return l;
}

RunDetails read_run_details(const db::Reader& reader, std::int64_t run_id, std::size_t max_points) {
  RunDetails d;
  const db::RunRecord run = reader.run(run_id);
  for (const auto& s : reader.runs())
    if (s.run.id == run_id) d.listing = listing_of(s);
  const auto channels = reader.channels(run_id);
  d.rows = step_rows(reader.compare(run_id), channels);
  for (const auto& e : reader.events(run_id)) {
    d.events.push_back({utc_of(run.to_utc_ns(e.t_ns)), qs(e.kind), qs(e.message), e.step_index});
  }
  db::SampleQuery q;
  q.decimation = db::Decimation::min_max;
  q.max_points = max_points;
  std::vector<db::Sample> load_samples, disp_samples;
  for (const auto& ch : channels) {
    SeriesView s{qs(ch.name), qs(ch.unit), {}};
    auto samples = reader.samples(ch.id, q);
    for (const auto& x : samples) {
      s.points.emplace_back(static_cast<double>(x.t_ns - run.monotonic_anchor_ns) * 1e-9, x.value);
    }
    if (ch.name == "load") load_samples = samples;
    if (ch.name == "displacement" || ch.name == "position") disp_samples = std::move(samples);
    d.series.push_back(std::move(s));
  }
  // The tester reads position and load in one transaction, so both channels carry the same
  // timestamps; pair them where they match.
  std::size_t j = 0;
  for (const auto& l : load_samples) {
    while (j < disp_samples.size() && disp_samples[j].t_ns < l.t_ns) ++j;
    if (j < disp_samples.size() && disp_samples[j].t_ns == l.t_ns) {
      d.load_vs_displacement.emplace_back(disp_samples[j].value, l.value);
    }
  }
  return d;
}

RunBrowserBackend::RunBrowserBackend(QObject* parent)
    : QObject(parent), tasks_(new TaskRunner(this)), fits_(new TaskRunner(this, 1, true)) {}

RunBrowserBackend::~RunBrowserBackend() {
  tasks_->wait();
  fits_->wait();
}

void RunBrowserBackend::wait() {
  tasks_->wait();
  fits_->wait();
}

void RunBrowserBackend::open_database(const QString& path) {
  struct Opened {
    std::shared_ptr<db::Reader> reader;
    QVector<RunListing> runs;
  };
  tasks_->run<Opened>(
      [path] {
        // Reader refuses (DatabaseError) a file that is missing, not SQLite, not tocdlab, or
        // of another schema, and never writes to it.
        if (!db::is_server_uri(path.toStdString()) && !QFileInfo::exists(path)) {
          throw std::runtime_error("no such file: " + path.toStdString());
        }
        Opened o;
        o.reader = std::make_shared<db::Reader>(path.toStdString());
        for (const auto& s : o.reader->runs()) o.runs.push_back(listing_of(s));
        return o;
      },
      [this, path](Opened& o) {
        reader_ = o.reader;
        path_ = path;
        emit database_opened(path, o.runs);
      },
      [this, path](const QString& message) {
        emit failed(tr("Opening %1").arg(QString::fromStdString(db::display_location(path.toStdString()))),
                    message);
      });
}

void RunBrowserBackend::refresh() {
  if (!reader_) return;
  auto reader = reader_;
  tasks_->run<QVector<RunListing>>(
      [reader] {
        QVector<RunListing> runs;
        for (const auto& s : reader->runs()) runs.push_back(listing_of(s));
        return runs;
      },
      [this](QVector<RunListing>& runs) { emit runs_listed(runs); },
      [this](const QString& message) { emit failed(tr("Listing runs"), message); });
}

void RunBrowserBackend::load_run(std::int64_t run_id) {
  if (!reader_) return;
  auto reader = reader_;
  tasks_->run<RunDetails>(
      [reader, run_id] { return read_run_details(*reader, run_id); },
      [this](RunDetails& d) { emit run_loaded(d); },
      [this, run_id](const QString& message) { emit failed(tr("Loading run %1").arg(run_id), message); });
}

void RunBrowserBackend::export_csv(std::int64_t run_id, const QString& path) {
  if (!reader_) return;
  auto reader = reader_;
  tasks_->run<QString>(
      [reader, run_id, path] {
        std::ofstream out(path.toStdString(), std::ios::binary);
        if (!out) throw std::runtime_error("cannot write " + path.toStdString());
        db::write_csv(*reader, run_id, db::CsvTable::steps, out);
        out.close();
        if (!out) throw std::runtime_error("writing " + path.toStdString() + " failed");
        return path;
      },
      [this](QString& p) { emit exported(p); },
      [this, run_id](const QString& message) { emit failed(tr("Exporting run %1").arg(run_id), message); });
}

bool RunBrowserBackend::fitting() const {
  return fits_->in_flight() > 0;
}

void RunBrowserBackend::fit_law(std::int64_t run_id, const QString& material) {
  if (!reader_ || fitting()) return;
  // A reader of its own: the browser's reader serves the other worker meanwhile.
  const std::string path = path_.toStdString();
  fits_->run<FittedLawView>(
      [this, path, run_id, material] {
        analysis::FittedComparisonOptions o;
        o.material = material.toStdString();
        o.progress = [this](const std::string& line) {
          QMetaObject::invokeMethod(
              this, [this, l = QString::fromStdString(line)] { emit fit_progress(l); }, Qt::QueuedConnection);
        };
        const db::Reader reader(path);
        const auto c = analysis::compare_with_fitted_law(reader, run_id, o);
        FittedLawView v;
        v.run_id = run_id;
        v.summary =
            c.identification
                ? tr("identified sample: stiffness x %1 (%2-%3, 95 %), its clearing optics and delay; "
                     "band: the optical parameters' 95 %")
                      .arg(c.factor, 0, 'f', 3)
                      .arg(c.factor_low, 0, 'f', 3)
                      .arg(c.factor_high, 0, 'f', 3)
            : c.fitted_here ? tr("published law x %1 (%2-%3, %4 %), %5 confidence laws")
                                  .arg(c.factor, 0, 'f', 3)
                                  .arg(c.factor_low, 0, 'f', 3)
                                  .arg(c.factor_high, 0, 'f', 3)
                                  .arg(100 * c.confidence, 0, 'f', 0)
                                  .arg(c.band_laws.size())
                            : tr("law of %1, %2 confidence laws").arg(material).arg(c.band_laws.size());
        for (const auto& s : c.steps) {
          if (!std::isfinite(s.T_fitted)) continue;
          v.points.push_back({s.index, s.nominal_strain, s.T_fitted, s.T_fitted_se, s.band_lo, s.band_hi});
        }
        return v;
      },
      [this](FittedLawView& v) { emit law_fitted(v); },
      [this, run_id](const QString& message) {
        emit failed(tr("Fitting the law of run %1").arg(run_id), message);
      });
}

}  // namespace tocd::gui
