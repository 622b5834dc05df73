#pragma once

// Which runs are recording right now. A process recording run N holds an open-file-description
// lock (Linux OFD lock) on byte N of "<db>-runlock". The kernel drops it when the process ends,
// however it ends, so a run marked `running` whose byte is not locked was left by a dead
// process and is `interrupted`.

#include <cstdint>
#include <filesystem>
#include <set>

namespace tocd::db::detail {

std::filesystem::path run_lock_path(const std::filesystem::path& db_path);

class RunLocks {
 public:
  /// `writable`: create the lock file and allow acquire(); otherwise probe only (the file may
  /// be absent: then no run is live).
  RunLocks(const std::filesystem::path& db_path, bool writable);
  ~RunLocks();
  RunLocks(const RunLocks&) = delete;
  RunLocks& operator=(const RunLocks&) = delete;

  /// Takes the lock of `run_id`; false when another process or Database object holds it.
  bool acquire(std::int64_t run_id);
  void release(std::int64_t run_id);
  /// True when this object or anyone else holds the lock of `run_id`.
  bool is_held(std::int64_t run_id) const;

 private:
  int fd_ = -1;
  std::set<std::int64_t> held_;
};

}  // namespace tocd::db::detail
