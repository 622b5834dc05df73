#include "run.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "tocd/core/log.hpp"

namespace tocd::acquisition {

namespace {

/// Gives each recorded channel of the present instruments its recorder slot.
void add_channels(Recorder& recorder, const InstrumentChannels& instruments,
                  const std::vector<std::int64_t>& ids) {
  std::size_t next = 0;
  for (InstrumentChannel* i : instruments.present()) {
    for (std::size_t k = 0; k < i->capabilities().channels.size(); ++k) {
      if (next >= ids.size())
        throw EngineError("internal: fewer channel rows than the instruments' channels");
      i->set_slot(k, recorder.add_channel(ids[next++]));
    }
  }
}

}  // namespace

Run::Run(RunParts parts, RunSetup setup, ScaledClock clock, const std::vector<std::int64_t>& channel_ids)
    : parts_(parts),
      setup_(std::move(setup)),
      clock_(clock),
      segment_start_ns_(clock_.now_ns()),
      events_(parts.db, recorder_, clock_, parts.control, parts.observer, setup_.run_id),
      faults_(parts.control, events_, parts.options.fault_tolerance_s),
      pollers_(clock_, events_, faults_, recorder_, parts.options.live_interval_s),
      predictions_(
          parts.db, parts.predictor,
          [this](const std::string& message, int step) { events_.emit("prediction", message, step); },
          [this](int step, const PredictedStep& p) {
            events_.notify([&](EngineObserver& o) { o.on_prediction(step, p); });
          }),
      sequencer_(SequencerParts{setup_, parts.options, clock_, parts.db, parts.control, events_, faults_,
                                recorder_, parts.instruments, pollers_, predictions_,
                                [this] { return progress(); }}) {
  add_channels(recorder_, parts.instruments, channel_ids);
}

Run::~Run() {
  sequencer_.join();
}

db::WriterOptions Run::writer_options() {
  db::WriterOptions wo = parts_.options.writer;
  // A commit that fails loses samples: that is a fault of the run, which ends interrupted
  // (what was committed stays; the run can be resumed once the storage is fixed).
  wo.on_failure = [this, user = parts_.options.writer.on_failure](const db::WriterFailure& f) {
    events_.storage_failed();
    faults_.trip(fmt::format("storage: a database commit failed, {} sample(s) lost ({} so far): {}",
                             f.samples, f.samples_total, f.error));
    if (user) user(f);
  };
  return wo;
}

void Run::start() {
  recorder_.start(parts_.db, writer_options());
  sequencer_.announce();
  pollers_.start(parts_.instruments.present());
  predictions_.start(setup_.run_id, setup_.protocol.sample.thickness_mm, [this] {
    // The run's predictions belong to it: its end is when the last of them landed (or was
    // given up), so every time stored with the run lies between its start and its end.
    try {
      parts_.db.mark_run_ended(setup_.run_id);
    } catch (const std::exception& e) {
      logger("acquisition")->error("run {}: cannot store its end: {}", setup_.run_id, e.what());
    }
    parts_.control.mark_finished();
  });
  sequencer_.start();
  running_ = true;
}

Progress Run::progress() const {
  Progress p;
  const RunControl::Position at = parts_.control.position();
  const Protocol& protocol = setup_.protocol;
  p.state = at.state;
  p.step_index = at.step;
  p.step_count = static_cast<int>(protocol.steps.size());
  p.elapsed_s = static_cast<double>(clock_.now_ns() - segment_start_ns_) * 1e-9;
  // Nominal time of the steps left, scaled by how the finished ones compared to nominal.
  const int n = p.step_count;
  const int done = std::max(0, p.step_index - setup_.first_step);
  const double per_step = n > 0 ? protocol.nominal_duration_s() / n : 0.0;
  const double observed = done > 0 ? p.elapsed_s / done : per_step;
  p.eta_s = std::max(0.0, (n - p.step_index) * std::max(per_step, observed) - (done > 0 ? 0.0 : p.elapsed_s));
  const InstrumentChannels& in = parts_.instruments;
  const TesterSnapshot tester = in.tester ? in.tester->latest() : TesterSnapshot{};
  p.displacement_mm = tester.displacement_mm;
  p.load_N = tester.load_N;
  p.power_W = in.power ? in.power->latest_W() : std::nan("");
  p.pressure_kPa = in.vacuum ? in.vacuum->latest_kPa() : std::nan("");
  p.transmission = p.power_W / setup_.baseline_W;
  return p;
}

EngineStats Run::stats() const {
  EngineStats s;
  s.samples_enqueued = recorder_.enqueued();
  s.samples_dropped = recorder_.dropped();
  s.poll_overruns = faults_.overruns();
  s.writer = recorder_.writer_stats();
  const PredictionQueue::Counts p = predictions_.counts();
  s.predictions_asked = p.asked;
  s.predictions_stored = p.stored;
  s.predictions_failed = p.failed;
  s.predictions_cancelled = p.cancelled;
  return s;
}

}  // namespace tocd::acquisition
