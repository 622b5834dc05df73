#include "tocd/core/thread_priority.hpp"

#include <cerrno>

#include <pthread.h>
#include <sched.h>
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
  const sched_param none{};
  const bool idle = ::pthread_setschedparam(::pthread_self(), SCHED_IDLE, &none) == 0;
  // Niceness as well: it still ranks the thread where SCHED_IDLE is refused (some containers).
  const bool nice = ::setpriority(PRIO_PROCESS, this_thread_id(), 19) == 0;
  return idle || nice;
}

bool this_thread_is_in_background() noexcept {
  int policy = 0;
  sched_param p{};
  if (::pthread_getschedparam(::pthread_self(), &policy, &p) == 0 && policy == SCHED_IDLE) return true;
  errno = 0;
  const int nice = ::getpriority(PRIO_PROCESS, this_thread_id());
  return errno == 0 && nice > 0;
}

}  // namespace tocd
