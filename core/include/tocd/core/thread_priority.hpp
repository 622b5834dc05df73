#pragma once

namespace tocd {

/// Moves the calling thread to the background: Linux's SCHED_IDLE policy where the kernel
/// grants it, else the weakest niceness (19). Threads it starts afterwards inherit this. Used
/// by computation that runs beside a recording (predictions, studies), so that it only gets
/// the CPU time the instruments' pollers and the writer leave. Returns false when neither
/// could be set (the thread then keeps its priority; nothing else changes).
bool run_this_thread_in_background() noexcept;

/// Whether the calling thread runs under SCHED_IDLE or at a niceness above 0 (for tests).
bool this_thread_is_in_background() noexcept;

}  // namespace tocd
