#pragma once

// The message a bad input is refused with, for tests that check what it names.

#include <string>

namespace tocd::test {

/// The message of the `E` that `f()` throws; empty when it throws nothing. An exception of
/// another type goes on up and fails the test.
template <class E, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return {};
}

}  // namespace tocd::test
