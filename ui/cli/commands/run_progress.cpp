#include "run_progress.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <signal.h>

namespace tocd::cli {

TerminalProgress::TerminalProgress() : TerminalProgress(std::cerr, stderr_progress_mode()) {}

void TerminalProgress::line(const std::string& text) {
  if (off_) return;
  if (live_ && status_shown_) out_ << "\r\33[K";
  status_shown_ = false;
  out_ << text << '\n' << std::flush;
}

void TerminalProgress::on_progress(const acquisition::Progress& p) {
  if (off_) return;
  std::lock_guard lock(mu_);
  const auto now = std::chrono::steady_clock::now();
  if (!live_ && now - last_status_ < std::chrono::seconds(5)) return;
  last_status_ = now;
  std::string readings;
  if (std::isfinite(p.displacement_mm))
    readings += fmt::format("  d {:7.4f} mm  F {:8.4f} N", p.displacement_mm, p.load_N);
  if (std::isfinite(p.pressure_kPa)) readings += fmt::format("  p {:6.2f} kPa", p.pressure_kPa);
  if (std::isfinite(p.power_W)) readings += fmt::format("  P {:.4g} W  T {:.4f}", p.power_W, p.transmission);
  constexpr int kWidth = 14;
  const int filled = p.step_count > 0 ? std::clamp(kWidth * p.step_index / p.step_count, 0, kWidth) : 0;
  const std::string text =
      fmt::format("step {}/{} [{}{}] {:<10}{}  elapsed {}  ETA {}", p.step_index + 1, p.step_count,
                  std::string(static_cast<std::size_t>(filled), '#'),
                  std::string(static_cast<std::size_t>(kWidth - filled), '.'),
                  acquisition::to_string(p.state), readings, clock_text(p.elapsed_s), clock_text(p.eta_s));
  if (live_) {
    out_ << "\r\33[K" << text << std::flush;
    status_shown_ = true;
  } else {
    out_ << text << '\n' << std::flush;
  }
}

void TerminalProgress::on_step_recorded(const acquisition::StepResult& s) {
  std::lock_guard lock(mu_);
  line(std::isfinite(s.load_N)
           ? fmt::format(
                 "step {}/{} recorded: d = {:.4f} mm (strain {:.3f}), load {:.4f} +- {:.4f} N, T = {:.5f}{}",
                 s.index + 1, s.step_count, s.displacement_mm, s.nominal_strain, s.load_N, s.load_std_N,
                 s.measured_T, s.settled ? "" : " (not settled)")
           : fmt::format("step {}/{} recorded: vacuum {:.2f} kPa (measured {:.2f}), T = {:.5f}", s.index + 1,
                         s.step_count, s.pressure_kPa, s.measured_pressure_kPa, s.measured_T));
}

void TerminalProgress::on_prediction(int step_index, const acquisition::PredictedStep& p) {
  std::lock_guard lock(mu_);
  // The latency (recording's end to stored) says whether predictions keep pace with the rig;
  // the prediction's own seconds leave out its wait behind the steps before it.
  const std::string stored = p.latency_s >= 0
                                 ? fmt::format(", stored {:.1f} s after its recording ended", p.latency_s)
                                 : std::string{};
  line(fmt::format("step {} predicted: T = {:.5f} +- {:.5f} ({:.1f} s{})", step_index + 1, p.T, p.T_stderr,
                   p.seconds, stored));
}

void TerminalProgress::on_event(const db::EventRecord& e) {
  if (e.kind != "interlock" && e.kind != "fault" && e.kind != "retry" && e.kind != "gap" &&
      e.kind != "operator" && e.kind != "baseline" &&
      !(e.kind == "prediction" && e.message.find("fail") != std::string::npos)) {
    return;
  }
  std::lock_guard lock(mu_);
  line(fmt::format("[{}] {}", e.kind, e.message));
}

struct AbortOnSignal::Impl {
  sigset_t set{}, old{};
  // Held by the watcher for the whole call on `engine`, and by attach(): once attach(nullptr)
  // has returned, no call on the engine it detached is running or can start, so the owner may
  // destroy that engine.
  std::mutex mu;
  acquisition::Engine* engine = nullptr;  // guarded by mu
  bool pending = false;                   // guarded by mu
  std::atomic<bool> done{false};
  int signals_seen = 0;  // watcher thread only
  std::thread watcher;
};

AbortOnSignal::AbortOnSignal(std::ostream& err) : impl_(new Impl) {
  sigemptyset(&impl_->set);
  sigaddset(&impl_->set, SIGINT);
  sigaddset(&impl_->set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &impl_->set, &impl_->old);
  impl_->watcher = std::thread([this, &err] {
    const timespec slice{0, 200'000'000};
    while (!impl_->done) {
      const int sig = sigtimedwait(&impl_->set, nullptr, &slice);
      if (sig != SIGINT && sig != SIGTERM) continue;
      const char* name = sig == SIGINT ? "SIGINT" : "SIGTERM";
      std::lock_guard lock(impl_->mu);
      if (auto* e = impl_->engine) {
        if (++impl_->signals_seen == 1) {
          err << "\n"
              << name << ": aborting (retracting the pin, keeping the data); again to stop the pin at once"
              << std::endl;
          e->abort(sig == SIGINT ? "SIGINT (Ctrl-C)" : "SIGTERM");
        } else {
          // The operator will not wait for the retraction: stop the pin where it is and end.
          err << "\n" << name << " again: stopping the pin where it is, no retraction" << std::endl;
          e->stop_now(sig == SIGINT ? "second SIGINT (Ctrl-C)" : "second SIGTERM");
        }
      } else {
        impl_->pending = true;  // before the run started: abort it as soon as it exists
      }
    }
  });
}

AbortOnSignal::~AbortOnSignal() {
  impl_->done = true;
  impl_->watcher.join();
  pthread_sigmask(SIG_SETMASK, &impl_->old, nullptr);
  delete impl_;
}

void AbortOnSignal::attach(acquisition::Engine* engine) {
  std::lock_guard lock(impl_->mu);
  impl_->engine = engine;
  if (engine && impl_->pending) engine->abort("signal received while starting");
}

}  // namespace tocd::cli
