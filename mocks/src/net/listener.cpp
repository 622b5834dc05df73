// The listening socket of a simulated instrument's TCP server.
#include "net/listener.hpp"

#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tocd/core/error.hpp"

namespace tocd::mocks::net {

namespace {
// A burst of connections (a load test, a restarted client pool) waits in the kernel's queue
// rather than being refused before the server had a chance to look at it.
constexpr int listen_backlog = 1024;  // the kernel caps it at net.core.somaxconn
}  // namespace

Listener listen_tcp(const std::string& host, int port, const std::string& what) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* ai = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &ai) != 0 || !ai)
    throw ConfigError(fmt::format("{}: cannot resolve \"{}\"", what, host));
  const int fd = ::socket(ai->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  const int one = 1;
  if (fd >= 0) ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (fd < 0 || ::bind(fd, ai->ai_addr, ai->ai_addrlen) != 0 || ::listen(fd, listen_backlog) != 0) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    ::freeaddrinfo(ai);
    throw ConfigError(fmt::format("{}: cannot listen on {}:{}: {}", what, host, port, why));
  }
  ::freeaddrinfo(ai);
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  const int bound_port = bound.ss_family == AF_INET6
                             ? ntohs(reinterpret_cast<const sockaddr_in6*>(&bound)->sin6_port)
                             : ntohs(reinterpret_cast<const sockaddr_in*>(&bound)->sin_port);
  return {fd, bound_port};
}

}  // namespace tocd::mocks::net
