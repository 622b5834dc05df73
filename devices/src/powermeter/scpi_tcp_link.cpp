// SCPI over a raw TCP socket: one line per message, '\n' terminated. Every wait is a poll()
// bounded by the caller's deadline; clear() reconnects, because a late answer still in flight
// would otherwise be read as the answer to the next query.
#include <cerrno>
#include <cstring>

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tocd/devices/power_meter_drivers.hpp"

namespace tocd::devices {
namespace {

constexpr std::size_t max_line = 64 * 1024;

int remaining_ms(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1 << 30));
}

class TcpLink final : public ScpiLink {
 public:
  explicit TcpLink(ScpiTcpAddress address)
      : address_(std::move(address)),
        description_(fmt::format("SCPI/TCP {}:{}", address_.host, address_.port)) {
    if (address_.host.empty()) throw ConfigError("SCPI/TCP power meter: no host given");
    if (address_.port <= 0 || address_.port > 65535)
      throw ConfigError(fmt::format("SCPI/TCP power meter: port {} is not a TCP port", address_.port));
  }
  ~TcpLink() override { close(); }

  std::string describe() const override { return description_; }
  bool is_open() const noexcept override { return fd_ >= 0; }

  void open(Clock::time_point deadline) override {
    close();
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(address_.port);
    if (const int rc = ::getaddrinfo(address_.host.c_str(), port.c_str(), &hints, &found); rc != 0)
      throw LinkError(LinkFailure::disconnected,
                      fmt::format("cannot resolve host \"{}\": {}", address_.host, ::gai_strerror(rc)));
    std::string why = "no address";
    for (addrinfo* a = found; a != nullptr && fd_ < 0; a = a->ai_next) {
      const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
      if (fd < 0) continue;
      if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0 && errno != EINPROGRESS) {
        why = std::strerror(errno);
        ::close(fd);
        continue;
      }
      pollfd p{fd, POLLOUT, 0};
      const int ready = ::poll(&p, 1, remaining_ms(deadline));
      int err = 0;
      socklen_t len = sizeof err;
      if (ready <= 0) {
        why = "connect timed out";
      } else if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0) {
        why = std::strerror(err);
      } else {
        const int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);  // small messages, answer at once
        fd_ = fd;
        break;
      }
      ::close(fd);
    }
    ::freeaddrinfo(found);
    if (fd_ < 0)
      throw LinkError(LinkFailure::disconnected, fmt::format("cannot connect to {}: {}", description_, why));
    buffer_.clear();
  }

  void close() noexcept override {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    buffer_.clear();
  }

  void write(std::string_view message, Clock::time_point deadline) override {
    require_open();
    if (peer_closed()) disconnected("the instrument closed the connection");
    std::string line(message);
    line += '\n';
    std::size_t sent = 0;
    while (sent < line.size()) {
      const ssize_t n = ::send(fd_, line.data() + sent, line.size() - sent, MSG_NOSIGNAL);
      if (n > 0) {
        sent += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)
        disconnected(fmt::format("send failed: {}", std::strerror(errno)));
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, remaining_ms(deadline)) <= 0)
        throw LinkError(LinkFailure::timeout, "the instrument does not accept data (send buffer full)");
    }
  }

  std::string read(Clock::time_point deadline) override {
    require_open();
    for (;;) {
      if (const auto nl = buffer_.find('\n'); nl != std::string::npos) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return line;
      }
      if (buffer_.size() > max_line)
        throw LinkError(LinkFailure::protocol,
                        fmt::format("answer longer than {} bytes without a newline terminator", max_line));
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, remaining_ms(deadline));
      if (ready == 0)
        throw LinkError(LinkFailure::timeout,
                        buffer_.empty()
                            ? "no answer"
                            : fmt::format("answer incomplete ({} bytes, no newline)", buffer_.size()));
      if (ready < 0 && errno != EINTR) disconnected(fmt::format("poll failed: {}", std::strerror(errno)));
      char chunk[4096];
      const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
      if (n == 0) disconnected("the instrument closed the connection");
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) continue;
        disconnected(fmt::format("recv failed: {}", std::strerror(errno)));
      }
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  void clear(Clock::time_point deadline) override {
    close();
    open(deadline);
  }

 private:
  void require_open() const {
    if (fd_ < 0) throw LinkError(LinkFailure::disconnected, "not connected");
  }
  [[noreturn]] void disconnected(const std::string& why) {
    close();
    throw LinkError(LinkFailure::disconnected, why);
  }
  /// True when the peer has closed: readable with nothing to read. Catches a dropped link
  /// before a command is written into it and lost.
  bool peer_closed() {
    pollfd p{fd_, POLLIN | POLLRDHUP, 0};
    if (::poll(&p, 1, 0) <= 0) return false;
    if (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) return true;
    char c;
    return ::recv(fd_, &c, 1, MSG_PEEK) == 0;
  }

  ScpiTcpAddress address_;
  std::string description_;
  int fd_ = -1;
  std::string buffer_;
};

}  // namespace

std::unique_ptr<ScpiLink> make_scpi_tcp_link(const ScpiTcpAddress& address) {
  return std::make_unique<TcpLink>(address);
}

}  // namespace tocd::devices
