#pragma once

#include <string>

namespace tocd::mocks::net {

/// A listening TCP socket (non-blocking, close-on-exec) and the port it is bound to.
struct Listener {
  int fd = -1;
  int port = 0;
};

/// Binds and listens on `host`:`port` (0 = any free port): the first address `host` resolves
/// to, so give a literal ("127.0.0.1", "::1") where the family matters. `what` names the
/// server in the ConfigError thrown when the address cannot be resolved or bound.
Listener listen_tcp(const std::string& host, int port, const std::string& what);

}  // namespace tocd::mocks::net
