#pragma once

namespace tocd {

/// Niceness of computation that runs beside a recording (predictions, studies, fits): CFS
/// then gives such a thread about a tenth of the CPU share of a normal one (weight 110 against
/// 1024), so a poller that wakes for its next reading runs at once, while the computation still
/// progresses on a machine kept busy by other work (SCHED_IDLE, tried first, starved it for as
/// long as the machine stayed busy: a run waited minutes for its predictions).
inline constexpr int kBackgroundNiceness = 10;

/// Lowers the calling thread to kBackgroundNiceness (Linux keeps niceness per thread); threads
/// it starts afterwards inherit it. Returns false when it could not be set (the thread then
/// keeps its priority; nothing else changes).
bool run_this_thread_in_background() noexcept;

/// Whether the calling thread runs at a niceness above 0 (for tests).
bool this_thread_is_in_background() noexcept;

}  // namespace tocd
