#include "progress.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <iostream>

#include <fmt/format.h>
#include <unistd.h>

namespace tocd::cli {

namespace {
std::atomic<bool> g_quiet{false};
constexpr auto kBarRedraw = std::chrono::milliseconds(100);  // ten redraws a second at most
}  // namespace

void set_progress_quiet(bool quiet) {
  g_quiet = quiet;
}
bool progress_quiet() {
  return g_quiet;
}

void say_recording_into(std::int64_t run_id, std::size_t steps, const std::string& database) {
  if (!progress_quiet())
    std::cerr << fmt::format("run {} ({} steps) recording into {}", run_id, steps, database) << std::endl;
}

ProgressMode stderr_progress_mode() {
  if (g_quiet) return ProgressMode::off;
  return ::isatty(STDERR_FILENO) != 0 ? ProgressMode::bar : ProgressMode::lines;
}

std::string clock_text(double s) {
  if (!std::isfinite(s) || s < 0) return "-";
  const auto t = static_cast<long>(s + 0.5);
  return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
                   : fmt::format("{}:{:02}", t / 60, t % 60);
}

std::string format_progress(const std::string& label, std::uint64_t done, std::uint64_t total,
                            const std::string& unit, double elapsed_s, int width) {
  const std::string unit_text = unit.empty() ? "" : " " + unit;
  if (total == 0)
    return done == 0 ? fmt::format("{}  elapsed {}", label, clock_text(elapsed_s))
                     : fmt::format("{}  {}{}  elapsed {}", label, done, unit_text, clock_text(elapsed_s));
  const double fraction = std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0);
  const int filled = static_cast<int>(fraction * width);
  const double rate = elapsed_s > 0 ? static_cast<double>(done) / elapsed_s : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total - std::min(done, total)) / rate : -1.0;
  return fmt::format("{} [{}{}] {:3.0f}%  {}/{}{}  {:.3g}/s  elapsed {}  ETA {}", label,
                     std::string(static_cast<std::size_t>(filled), '#'),
                     std::string(static_cast<std::size_t>(width - filled), '.'), 100.0 * fraction, done,
                     total, unit_text, rate, clock_text(elapsed_s), done >= total ? "0:00" : clock_text(eta));
}

ProgressBar::ProgressBar(std::ostream& out, ProgressMode mode, std::string label, std::uint64_t total,
                         std::string unit, std::chrono::milliseconds line_interval)
    : out_(out),
      mode_(mode),
      label_(std::move(label)),
      unit_(std::move(unit)),
      line_interval_(line_interval),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_),
      total_(total) {}

ProgressBar::ProgressBar(std::string label, std::uint64_t total, std::string unit)
    : ProgressBar(std::cerr, stderr_progress_mode(), std::move(label), total, std::move(unit)) {}

ProgressBar::~ProgressBar() {
  finish();
}

void ProgressBar::set_total(std::uint64_t total) {
  std::lock_guard lock(mu_);
  total_ = total;
}

void ProgressBar::update(std::uint64_t done) {
  if (mode_ == ProgressMode::off) return;
  std::lock_guard lock(mu_);
  if (finished_) return;
  done_ = done;
  const auto now = std::chrono::steady_clock::now();
  const auto interval = mode_ == ProgressMode::bar ? std::chrono::milliseconds(kBarRedraw) : line_interval_;
  if (now - last_draw_ < interval) return;
  last_draw_ = now;
  draw(done, false);
}

void ProgressBar::note(const std::string& line) {
  if (mode_ == ProgressMode::off) return;
  std::lock_guard lock(mu_);
  if (mode_ == ProgressMode::bar && drawn_ && !finished_) out_ << "\r\33[K";
  out_ << line << (line.ends_with('\n') ? "" : "\n");
  if (mode_ == ProgressMode::bar && !finished_) draw(done_, false);
  out_ << std::flush;
}

void ProgressBar::finish() {
  if (mode_ == ProgressMode::off) return;
  std::lock_guard lock(mu_);
  if (finished_) return;
  finished_ = true;
  // A job shorter than one interval said nothing in line mode: it needs no closing line either.
  if (mode_ == ProgressMode::lines && !drawn_) return;
  draw(done_, true);
}

void ProgressBar::draw(std::uint64_t done, bool final) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string text = format_progress(label_, done, total_, unit_, elapsed);
  if (mode_ == ProgressMode::bar) {
    out_ << "\r\33[K" << text;
    if (final) out_ << '\n';
  } else {
    out_ << text << '\n';
  }
  out_ << std::flush;
  drawn_ = true;
}

struct ElapsedTicker::State {
  explicit State(std::string label) : bar(std::move(label), 0, "") {}
  ProgressBar bar;
  std::mutex mu;
  std::condition_variable wake;
  bool stop = false;  // guarded by mu
};

ElapsedTicker::ElapsedTicker(std::string label) : state_(std::make_unique<State>(std::move(label))) {
  if (stderr_progress_mode() == ProgressMode::off) return;
  thread_ = std::thread([s = state_.get()] {
    std::unique_lock lock(s->mu);
    while (!s->wake.wait_for(lock, std::chrono::milliseconds(200), [s] { return s->stop; })) s->bar.update(0);
  });
}

ElapsedTicker::~ElapsedTicker() {
  {
    std::lock_guard lock(state_->mu);
    state_->stop = true;
  }
  state_->wake.notify_all();
  if (thread_.joinable()) thread_.join();
  state_->bar.finish();
}

PhasedProgress::PhasedProgress(std::string uncounted_label, std::string counted_label, std::string unit)
    : counted_label_(std::move(counted_label)), unit_(std::move(unit)) {
  ticker_.emplace(std::move(uncounted_label));
}

void PhasedProgress::update(std::uint64_t done, std::uint64_t total) {
  std::lock_guard lock(mu_);
  if (!bar_) {
    ticker_.reset();  // ends the elapsed-time line before the bar starts
    bar_.emplace(counted_label_, total, unit_);
  }
  bar_->update(done);
}

void PhasedProgress::finish() {
  std::lock_guard lock(mu_);
  ticker_.reset();
  if (bar_) bar_->finish();
}

}  // namespace tocd::cli
