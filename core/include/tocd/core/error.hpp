#pragma once

#include <stdexcept>
#include <string>

namespace tocd {

/// Base of every error tocdlab raises on bad input or failed I/O. The message is written for
/// a lab user: what was being read or talked to, what was expected, what was found.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A configuration, protocol or input file that cannot be used as written.
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// Work stopped on request (an operator's abort, a signal) before it finished: not a fault of
/// the input. Whoever asked for the stop knows why; the message says where the work stood.
class Cancelled : public Error {
 public:
  using Error::Error;
};

}  // namespace tocd
