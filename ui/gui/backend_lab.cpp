#include "backend_lab.hpp"

#include <algorithm>
#include <chrono>

#include "background.hpp"
#include "qt_text.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/devices/errors.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"

namespace tocd::gui {

namespace {

InstrumentIdentity identity_of(InstrumentKind kind, const devices::Identity& id) {
  return {kind, qs(id.vendor), qs(id.model), qs(id.serial), qs(id.firmware)};
}

constexpr auto kPollPeriod = std::chrono::milliseconds(250);

// The sample `tocdlab demo` measures (the demo protocol's thickness and deepest step), so the
// window's demo and the command line's record the same sample; prepared once, then cached.
std::shared_ptr<mocks::TissueModel> default_sample(const mocks::SampleTruth& truth) {
  const acquisition::Protocol demo = acquisition::demo_protocol();
  double deepest = 0;
  for (const auto& s : demo.steps) deepest = std::max(deepest, s.displacement_mm);
  mocks::DefaultSampleOptions o;
  o.cache_dir = mocks::default_sim_tissue_cache_dir();
  return mocks::make_default_sample(demo.sample.thickness_mm, deepest, truth, o);
}

}  // namespace

struct LabBackend::Connected {
  devices::LabConfig config;
  std::unique_ptr<mocks::SimulatedLab> simulated;
  double clock_factor = 1.0;
  std::shared_ptr<devices::LabInstruments> instruments;
  QVector<InstrumentIdentity> identities;
};

LabBackend::LabBackend(QObject* parent) : QObject(parent), tasks_(new TaskRunner(this)) {}

LabBackend::~LabBackend() {
  tasks_->wait();
  stop_polling();
  instruments_.reset();
  simulated_.reset();
}

void LabBackend::wait() {
  tasks_->wait();
}

namespace {

// Connects to every instrument of `config` and asks each who it is (worker thread).
void open_and_identify(LabBackend* /*unused*/, const devices::LabConfig& config,
                       std::shared_ptr<devices::LabInstruments>& instruments,
                       QVector<InstrumentIdentity>& identities) {
  instruments = std::make_shared<devices::LabInstruments>(devices::open_lab(config));
  if (instruments->tester) {
    identities.push_back(identity_of(InstrumentKind::tester, instruments->tester->identity()));
  }
  if (instruments->power_meter) {
    identities.push_back(identity_of(InstrumentKind::power_meter, instruments->power_meter->identity()));
  }
  if (instruments->vacuum) {
    identities.push_back(identity_of(InstrumentKind::vacuum, instruments->vacuum->identity()));
  }
}

}  // namespace

void LabBackend::connect_lab_file(const QString& path) {
  disconnect_lab();
  tasks_->run<std::shared_ptr<Connected>>(
      [this, path] {
        auto c = std::make_shared<Connected>();
        c->config = devices::load_lab_config(path.toStdString());
        open_and_identify(this, c->config, c->instruments, c->identities);
        return c;
      },
      [this](std::shared_ptr<Connected>& c) { finish_connect(c); },
      [this, path](const QString& message) {
        emit failed(tr("Connecting to the lab in %1").arg(path), message);
      });
}

void LabBackend::connect_simulated(mocks::SimulatedLabOptions options, const mocks::SampleTruth& truth) {
  disconnect_lab();
  tasks_->run<std::shared_ptr<Connected>>(
      [this, options, truth]() mutable {
        auto c = std::make_shared<Connected>();
        if (!options.tissue) options.tissue = default_sample(truth);
        c->simulated = std::make_unique<mocks::SimulatedLab>(options);
        c->clock_factor = options.clock_factor;
        c->config = c->simulated->config();
        open_and_identify(this, c->config, c->instruments, c->identities);
        return c;
      },
      [this](std::shared_ptr<Connected>& c) { finish_connect(c); },
      [this](const QString& message) { emit failed(tr("Starting the simulated lab"), message); });
}

void LabBackend::finish_connect(std::shared_ptr<Connected> c) {
  config_ = c->config;
  simulated_ = std::move(c->simulated);
  clock_factor_ = c->clock_factor;
  // Poll first: a slot of connected() may take the instruments for a run at once.
  start_polling(std::move(c->instruments));
  emit connected(lab_name(), c->identities);
}

void LabBackend::disconnect_lab() {
  stop_polling();
  instruments_.reset();
  const bool was = config_.has_value();
  config_.reset();
  simulated_.reset();
  clock_factor_ = 1.0;
  if (was) emit disconnected();
}

QString LabBackend::config_text() const {
  return config_ ? qs(devices::to_toml(*config_)) : QString();
}

QString LabBackend::lab_name() const {
  if (!config_) return {};
  return config_->name.empty() ? tr("lab") : qs(config_->name);
}

bool LabBackend::has(InstrumentKind kind) const {
  if (!config_) return false;
  switch (kind) {
    case InstrumentKind::tester:
      return config_->tester.has_value();
    case InstrumentKind::power_meter:
      return config_->power_meter.has_value();
    case InstrumentKind::vacuum:
      return config_->vacuum.has_value();
  }
  return false;
}

void LabBackend::start_polling(std::shared_ptr<devices::LabInstruments> instruments) {
  stop_polling();
  instruments_ = std::move(instruments);
  stop_poller_ = false;
  auto inst = instruments_;
  poller_ = std::thread([this, inst] {
    // Readings go to the GUI thread as queued calls; `this` outlives the thread because
    // stop_polling() joins it before the object goes.
    const auto post = [this](InstrumentReading r) {
      QMetaObject::invokeMethod(
          this, [this, r] { emit reading(r); }, Qt::QueuedConnection);
    };
    const auto post_error = [this](InstrumentKind k, const QString& m) {
      QMetaObject::invokeMethod(
          this, [this, k, m] { emit instrument_error(k, m); }, Qt::QueuedConnection);
    };
    while (!stop_poller_.load()) {
      const auto next = std::chrono::steady_clock::now() + kPollPeriod;
      if (inst->tester) {
        try {
          const auto r = inst->tester->read();
          post({InstrumentKind::tester, r.position_mm, r.load_N, r.status.fault || r.status.limit,
                r.status.limit
                    ? tr("limit tripped")
                    : (r.status.fault ? tr("fault code %1").arg(r.status.fault_code) : QString())});
        } catch (const std::exception& e) {
          post_error(InstrumentKind::tester, QString::fromUtf8(e.what()));
        }
      }
      if (inst->power_meter) {
        try {
          const auto r = inst->power_meter->measure();
          post({InstrumentKind::power_meter, r.power_W, 0, r.over_range,
                r.over_range ? tr("over range") : QString()});
        } catch (const std::exception& e) {
          post_error(InstrumentKind::power_meter, QString::fromUtf8(e.what()));
        }
      }
      if (inst->vacuum) {
        try {
          const auto r = inst->vacuum->read();
          post({InstrumentKind::vacuum, r.pressure_kPa, r.setpoint_kPa, r.error_code != 0,
                r.error_code ? tr("error code %1").arg(r.error_code) : QString()});
        } catch (const std::exception& e) {
          post_error(InstrumentKind::vacuum, QString::fromUtf8(e.what()));
        }
      }
      while (!stop_poller_.load() && std::chrono::steady_clock::now() < next) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
  });
}

void LabBackend::stop_polling() {
  stop_poller_ = true;
  if (poller_.joinable()) poller_.join();
}

acquisition::InstrumentSet LabBackend::take_instruments() {
  stop_polling();
  acquisition::InstrumentSet set;
  if (instruments_) set = acquisition::to_instrument_set(std::move(*instruments_));
  instruments_.reset();
  return set;
}

void LabBackend::reconnect() {
  if (!config_) return;
  const devices::LabConfig config = *config_;
  tasks_->run<std::shared_ptr<devices::LabInstruments>>(
      [this, config] {
        std::shared_ptr<devices::LabInstruments> inst;
        QVector<InstrumentIdentity> ids;
        open_and_identify(this, config, inst, ids);
        return inst;
      },
      [this](std::shared_ptr<devices::LabInstruments>& inst) {
        if (config_) start_polling(inst);
      },
      [this](const QString& message) { emit failed(tr("Reconnecting to the lab"), message); });
}

}  // namespace tocd::gui
