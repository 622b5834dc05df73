#pragma once

// Waiting for something another thread or process does, without a fixed sleep.

#include <chrono>
#include <thread>

namespace tocd::test {

/// Polls `pred` every `poll` for up to `seconds` of real time; true as soon as it holds.
template <class Pred>
bool eventually(Pred pred, double seconds = 20.0,
                std::chrono::milliseconds poll = std::chrono::milliseconds(2)) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(poll);
  }
  return pred();
}

}  // namespace tocd::test
