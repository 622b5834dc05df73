#include "recorder.hpp"

namespace tocd::acquisition {

int Recorder::add_channel(std::int64_t id) {
  channel_.push_back(id);
  std::lock_guard lock(window_mu_);
  window_.resize(channel_.size());
  return static_cast<int>(channel_.size()) - 1;
}

void Recorder::start(db::Database& db, db::WriterOptions options) {
  writer_ = std::make_unique<db::Writer>(db, std::move(options));
}

void Recorder::stop() {
  if (writer_) writer_->stop();
}

void Recorder::add(int slot, std::int64_t t_ns, double value) {
  if (writer_->enqueue(db::Sample{channel(slot), t_ns, value})) {
    ++enqueued_;
  } else {
    ++dropped_;
  }
  std::lock_guard lock(window_mu_);
  if (window_open_) window_[static_cast<std::size_t>(slot)].add(value);
}

bool Recorder::enqueue_event(const db::EventRecord& event) {
  return writer_ && writer_->enqueue(event);
}

void Recorder::open_window() {
  std::lock_guard lock(window_mu_);
  for (auto& s : window_) s.reset();
  window_open_ = true;
}

std::vector<RunningStats> Recorder::close_window() {
  std::lock_guard lock(window_mu_);
  window_open_ = false;
  return window_;
}

db::WriterStats Recorder::writer_stats() const {
  return writer_ ? writer_->stats() : db::WriterStats{};
}

}  // namespace tocd::acquisition
