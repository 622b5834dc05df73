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

}  // namespace tocd
