#include "tocd/core/thread_priority.hpp"

#include <cerrno>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace tocd {

namespace {

// setpriority(PRIO_PROCESS, tid) sets one thread's niceness on Linux (POSIX would have it for
// the whole process; Linux keeps niceness per thread).
id_t this_thread_id() noexcept {
  return static_cast<id_t>(::syscall(SYS_gettid));
}

}  // namespace

bool run_this_thread_in_background() noexcept {
  errno = 0;
  const int now = ::getpriority(PRIO_PROCESS, this_thread_id());
  if (errno == 0 && now >= kBackgroundNiceness) return true;  // already there (or lower)
  return ::setpriority(PRIO_PROCESS, this_thread_id(), kBackgroundNiceness) == 0;
}

bool this_thread_is_in_background() noexcept {
  errno = 0;
  const int nice = ::getpriority(PRIO_PROCESS, this_thread_id());
  return errno == 0 && nice > 0;
}

}  // namespace tocd
