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

/// A module's own kind of error: a type of its own to catch (told apart by the tag `Module`),
/// derived from `Base` (ConfigError for bad input, Error for what is not the input's fault),
/// with nothing more to write per module. E.g. `using FeError = ErrorOf<struct FeModule>;`.
template <class Module, class Base = ConfigError>
class ErrorOf : public Base {
 public:
  using Base::Base;
};

/// Work stopped on request (an operator's abort, a signal) before it finished: not a fault of
/// the input. Whoever asked for the stop knows why; the message says where the work stood.
class Cancelled : public Error {
 public:
  using Error::Error;
};

}  // namespace tocd
