#include "run_lock.hpp"

#include <cerrno>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "tocd/db/database.hpp"

namespace tocd::db::detail {

namespace {
struct flock byte_lock(short type, std::int64_t run_id) {
  struct flock l {};
  l.l_type = type;
  l.l_whence = SEEK_SET;
  l.l_start = static_cast<off_t>(run_id);
  l.l_len = 1;
  l.l_pid = 0;  // required 0 for OFD locks
  return l;
}
}  // namespace

std::filesystem::path run_lock_path(const std::filesystem::path& db_path) {
  return db_path.string() + "-runlock";
}

RunLocks::RunLocks(const std::filesystem::path& db_path, bool writable) {
  const auto p = run_lock_path(db_path);
  fd_ = writable ? ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)
                 : ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0 && writable)
    throw DatabaseError("cannot open the run lock file '" + p.string() + "': " + std::strerror(errno));
}

RunLocks::~RunLocks() {
  if (fd_ >= 0) ::close(fd_);  // releases every lock this object holds
}

bool RunLocks::acquire(std::int64_t run_id) {
  if (held_.count(run_id)) return true;
  struct flock l = byte_lock(F_WRLCK, run_id);
  if (::fcntl(fd_, F_OFD_SETLK, &l) != 0) {
    if (errno == EAGAIN || errno == EACCES) return false;
    throw DatabaseError(std::string("cannot lock run in the run lock file: ") + std::strerror(errno));
  }
  held_.insert(run_id);
  return true;
}

void RunLocks::release(std::int64_t run_id) {
  if (!held_.erase(run_id)) return;
  struct flock l = byte_lock(F_UNLCK, run_id);
  ::fcntl(fd_, F_OFD_SETLK, &l);
}

bool RunLocks::is_held(std::int64_t run_id) const {
  if (held_.count(run_id)) return true;
  if (fd_ < 0) return false;
  // Probe with a read lock: it conflicts with the write lock of a recording process.
  struct flock l = byte_lock(F_RDLCK, run_id);
  if (::fcntl(fd_, F_OFD_GETLK, &l) != 0) return false;
  return l.l_type != F_UNLCK;
}

}  // namespace tocd::db::detail
