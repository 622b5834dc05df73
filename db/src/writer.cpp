#include "tocd/db/writer.hpp"

#include <algorithm>
#include <array>
#include <condition_variable>
#include <ctime>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "batch_rows.hpp"
#include "pg/pg_batch.hpp"
#include "schema.hpp"
#include "sqlite_util.hpp"
#include "tocd/core/log.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/location.hpp"

namespace tocd::db {

using Clock = std::chrono::steady_clock;

struct Writer::Impl {
  WriterOptions opt;
  detail::Connection c;                     // an SQLite file, or
  std::unique_ptr<pg::BatchWriter> server;  // a PostgreSQL server

  // Guarded by mu: the queue and the counters.
  mutable std::mutex mu;
  std::condition_variable wake;      // writer thread: work or stop
  std::condition_variable progress;  // flush(): a batch finished
  std::vector<Sample> samples;
  std::vector<EventRecord> events;
  Clock::time_point first_pending{};
  std::uint64_t accepted_items = 0;   // samples + events accepted so far
  std::uint64_t processed_items = 0;  // committed, rejected or failed
  bool flush_requested = false;
  bool stopping = false;
  bool stopped = false;
  WriterStats st;
  double batch_ms_sum = 0;

  std::thread thread;

  // Writer thread only.
  std::unordered_map<std::int64_t, std::int64_t> channel_run;  // channel id -> run id (0: unknown)
  std::unordered_map<std::int64_t, bool> run_exists;

  Impl(const std::filesystem::path& path, WriterOptions o) : opt(o) {
    if (is_server_uri(path.string())) {
      server = std::make_unique<pg::BatchWriter>(path.string());
      thread = std::thread([this] { loop(); });
      return;
    }
    c = detail::open_read_only(path);  // identity and schema checks, without writing
    c = detail::Connection(path, SQLITE_OPEN_READWRITE);
    detail::configure_read_write(c);
    // A larger page cache keeps the hot ends of the samples table and of its (channel, time)
    // index in memory across batches.
    c.exec("PRAGMA cache_size = -65536");  // KiB: 64 MiB
    if (opt.max_page_count > 0) c.exec(fmt::format("PRAGMA max_page_count = {}", opt.max_page_count));
    thread = std::thread([this] { loop(); });
  }

  std::size_t pending() const { return samples.size() + events.size(); }

  bool accept_one_locked() {
    if (stopped || pending() >= opt.queue_capacity) {
      ++st.dropped;
      return false;
    }
    if (pending() == 0) {
      first_pending = Clock::now();
      wake.notify_one();
    }
    ++st.enqueued;
    ++accepted_items;
    return true;
  }

  void after_accept_locked() {
    st.queue_high_water = std::max(st.queue_high_water, pending());
    if (pending() >= opt.batch_rows) wake.notify_one();
  }

  // Queues one sample or event on `queue`, or counts it dropped (queue full, writer stopped).
  template <class Item>
  bool enqueue_one_locked(std::vector<Item>& queue, const Item& item) noexcept {
    if (!accept_one_locked()) return false;
    try {
      queue.push_back(item);
    } catch (...) {  // out of memory: count it dropped rather than throw into acquisition
      --st.enqueued;
      --accepted_items;
      ++st.dropped;
      return false;
    }
    after_accept_locked();
    return true;
  }

  void loop() {
    std::vector<Sample> batch;
    std::vector<EventRecord> batch_events;
    std::unique_lock lk(mu);
    for (;;) {
      // Wait until the oldest row is batch_interval old, batch_rows wait, flush, or stop.
      while (!stopping && !flush_requested && pending() < opt.batch_rows) {
        if (pending() == 0)
          wake.wait(lk);
        else if (wake.wait_until(lk, first_pending + opt.batch_interval) == std::cv_status::timeout)
          break;
      }
      if (pending() == 0) {
        flush_requested = false;
        progress.notify_all();
        if (stopping) break;
        continue;
      }
      const Clock::time_point oldest = first_pending;  // enqueue time of the batch's first row
      batch.swap(samples);
      batch_events.swap(events);
      if (pending() == 0 && !stopping) flush_requested = false;
      lk.unlock();

      // A backlog is committed in transactions of at most batch_rows rows, so progress (and
      // durability) advances batch by batch even when the queue has grown long.
      const std::size_t chunk = std::max<std::size_t>(1, opt.batch_rows);
      for (std::size_t from = 0; from < batch.size() || (from == 0 && !batch_events.empty()); from += chunk) {
        const std::size_t n = std::min(chunk, batch.size() - from);
        const std::span<const Sample> part(batch.data() + from, n);
        const std::span<const EventRecord> evs =
            from == 0 ? std::span<const EventRecord>(batch_events) : std::span<const EventRecord>();
        const auto t0 = Clock::now();
        std::uint64_t written = 0, rejected = 0, failed = 0;
        std::string error;
        write_batch(part, evs, written, rejected, failed, error);
        const auto t1 = Clock::now();
        const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
        const double delay_ms = std::chrono::duration<double, std::milli>(t1 - oldest).count();
        timespec cpu{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu);

        lk.lock();
        st.written += written;
        st.rejected += rejected;
        st.failed += failed;
        const std::uint64_t failed_samples = failed > 0 ? n : 0;
        st.failed_samples += failed_samples;
        const WriterFailure failure{failed_samples, failed > 0 ? evs.size() : 0, st.failed_samples, error};
        st.writer_cpu_seconds = static_cast<double>(cpu.tv_sec) + 1e-9 * static_cast<double>(cpu.tv_nsec);
        if (!error.empty()) st.last_error = error;
        if (failed == 0) {
          ++st.batches;
          batch_ms_sum += ms;
          st.last_batch_ms = ms;
          st.max_batch_ms = std::max(st.max_batch_ms, ms);
          st.max_commit_delay_ms = std::max(st.max_commit_delay_ms, delay_ms);
          st.mean_batch_ms = batch_ms_sum / static_cast<double>(st.batches);
        }
        processed_items += n + evs.size();
        progress.notify_all();
        lk.unlock();
        if (failed > 0) report(failure);
      }
      batch.clear();
      batch_events.clear();
      lk.lock();
    }
    stopped = true;
  }

  void report(const WriterFailure& f) noexcept {
    if (!opt.on_failure) return;
    try {
      opt.on_failure(f);
    } catch (const std::exception& e) {
      logger("db")->error("writer: the failure handler threw: {}", e.what());
    } catch (...) {
      logger("db")->error("writer: the failure handler threw");
    }
  }

  // Resolve a channel's run once; unknown channels are re-queried (they may have been added
  // since), so a race between add_channel and the first sample cannot lose data.
  std::int64_t run_of(std::int64_t channel_id) {
    const auto it = channel_run.find(channel_id);
    if (it != channel_run.end() && it->second != 0) return it->second;
    detail::Statement q(c, "SELECT run_id FROM channels WHERE id = ?");
    q.bind(1, channel_id);
    const std::int64_t run = q.step() ? q.col_int(0) : 0;
    channel_run[channel_id] = run;
    return run;
  }

  bool has_run(std::int64_t run_id) {
    const auto it = run_exists.find(run_id);
    if (it != run_exists.end() && it->second) return true;
    detail::Statement q(c, "SELECT 1 FROM runs WHERE id = ?");
    q.bind(1, run_id);
    return run_exists[run_id] = q.step();
  }

  void write_batch(std::span<const Sample> batch, std::span<const EventRecord> evs, std::uint64_t& written,
                   std::uint64_t& rejected, std::uint64_t& failed, std::string& error) {
    // A failed commit (e.g. disk full) is retried a few times before the batch is counted failed.
    for (int attempt = 0; attempt < 3; ++attempt) {
      written = rejected = 0;
      try {
        if (server) {
          server->write(batch, evs, written, rejected, error);
          failed = 0;
          return;
        }
        // Back to back, batch after batch of a backlog, this thread would keep the write lock
        // from the run's own writes (write_turns.hpp): they go first.
        c.let_waiting_writers_first();
        detail::Transaction t(c);
        detail::Statement ins(
            c, "INSERT INTO samples(run_id, channel_id, t_ns, value, segment) VALUES(?,?,?,?,?)");
        // A run's anchor segment cannot change while it records (resume_run needs it stopped):
        // one look-up per run and batch.
        std::unordered_map<std::int64_t, std::int64_t> segment;
        const auto segment_of = [&](std::int64_t run) {
          const auto it = segment.find(run);
          if (it != segment.end()) return it->second;
          detail::Statement q(c, "SELECT coalesce(max(segment), 0) FROM run_anchors WHERE run_id = ?");
          q.bind(1, run);
          return segment[run] = q.step() ? q.col_int(0) : 0;
        };
        detail::write_known_samples(
            batch, [&](std::int64_t channel_id) { return run_of(channel_id); },
            [&](std::int64_t run, const Sample& s) {
              ins.bind(1, run)
                  .bind(2, s.channel_id)
                  .bind(3, s.t_ns)
                  .bind(4, s.value)
                  .bind(5, segment_of(run));
              ins.step();
              sqlite3_reset(ins.get());  // every parameter is bound again for the next row
            },
            written, rejected, error);
        detail::Statement ev(
            c,
            "INSERT INTO events(run_id, t_ns, kind, message, step_index, data_json, segment) "
            "VALUES(?,?,?,?,?,?,?)");
        detail::write_known_events(
            evs, [&](std::int64_t run_id) { return has_run(run_id); },
            [&](const EventRecord& e) {
              ev.bind(1, e.run_id).bind(2, e.t_ns).bind(3, e.kind).bind(4, e.message);
              if (e.step_index >= 0) ev.bind(5, e.step_index);
              if (!e.data_json.empty()) ev.bind(6, e.data_json);
              ev.bind(7, segment_of(e.run_id));
              ev.run();
              ev.reset();
            },
            written, rejected, error);
        t.commit();
        failed = 0;
        return;
      } catch (const std::exception& e) {  // a database error (disk full, ...) or out of memory
        error = e.what();
        logger("db")->error("writer batch of {} rows failed (attempt {}): {}", batch.size() + evs.size(),
                            attempt + 1, error);
        std::this_thread::sleep_for(std::chrono::milliseconds(50 << attempt));
      }
    }
    written = rejected = 0;
    failed = batch.size() + evs.size();
  }
};

Writer::Writer(const std::filesystem::path& db_path, WriterOptions options)
    : impl_(std::make_unique<Impl>(db_path, options)) {}

Writer::Writer(const Database& db, WriterOptions options) : Writer(db.path(), options) {}

Writer::~Writer() {
  stop();
}

bool Writer::enqueue(const Sample& sample) noexcept {
  std::lock_guard lk(impl_->mu);
  return impl_->enqueue_one_locked(impl_->samples, sample);
}

std::size_t Writer::enqueue(std::span<const Sample> samples) noexcept {
  std::lock_guard lk(impl_->mu);
  auto& m = *impl_;
  const std::size_t room =
      m.stopped || m.pending() >= m.opt.queue_capacity ? 0 : m.opt.queue_capacity - m.pending();
  std::size_t n = std::min(room, samples.size());
  try {
    m.samples.insert(m.samples.end(), samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(n));
  } catch (...) {
    n = 0;
  }
  if (n > 0 && m.pending() == n) {
    m.first_pending = Clock::now();
    m.wake.notify_one();
  }
  m.st.enqueued += n;
  m.accepted_items += n;
  m.st.dropped += samples.size() - n;
  m.after_accept_locked();
  return n;
}

bool Writer::enqueue(const EventRecord& event) noexcept {
  std::lock_guard lk(impl_->mu);
  return impl_->enqueue_one_locked(impl_->events, event);
}

void Writer::flush() {
  std::unique_lock lk(impl_->mu);
  const std::uint64_t target = impl_->accepted_items;
  if (impl_->processed_items >= target || impl_->stopped) return;
  impl_->flush_requested = true;
  impl_->wake.notify_one();
  impl_->progress.wait(lk, [&] { return impl_->processed_items >= target || impl_->stopped; });
}

void Writer::stop() {
  {
    std::lock_guard lk(impl_->mu);
    if (impl_->stopping) {
      if (!impl_->thread.joinable()) return;
    }
    impl_->stopping = true;
    impl_->wake.notify_one();
  }
  if (impl_->thread.joinable()) impl_->thread.join();
}

WriterStats Writer::stats() const {
  std::lock_guard lk(impl_->mu);
  WriterStats s = impl_->st;
  s.queue_depth = impl_->pending();
  return s;
}

const WriterOptions& Writer::options() const noexcept {
  return impl_->opt;
}

}  // namespace tocd::db
