#pragma once

// A loopback TCP proxy between a driver and a simulated instrument that, while slowed,
// passes the instrument's answers on one byte at a time with a pause after each: an
// instrument (or a congested gateway) that trickles its answers, each byte inside libmodbus's
// byte timeout, so that only a bound on the whole answer catches it.

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace tocd::acquisition::testing {

class TrickleProxy {
 public:
  /// Forwards 127.0.0.1:port() to 127.0.0.1:`target_port`.
  explicit TrickleProxy(int target_port) : target_port_(target_port) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(listen_fd_, 8) != 0)
      throw std::runtime_error("trickle proxy: cannot listen on loopback");
    socklen_t len = sizeof a;
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    accepting_ = std::thread([this] { accept_loop(); });
  }
  ~TrickleProxy() {
    stop_ = true;
    accepting_.join();  // no pump starts after this
    {
      std::lock_guard lock(mu_);
      for (const int fd : fds_) ::shutdown(fd, SHUT_RDWR);
    }
    for (auto& t : threads_) t.join();
    std::lock_guard lock(mu_);
    for (const int fd : fds_) ::close(fd);
    ::close(listen_fd_);
  }
  TrickleProxy(const TrickleProxy&) = delete;
  TrickleProxy& operator=(const TrickleProxy&) = delete;

  int port() const { return port_; }
  /// From now on every answer byte is followed by `gap` (zero: answers pass at once).
  void slow(std::chrono::milliseconds gap) { gap_ms_ = static_cast<int>(gap.count()); }

 private:
  void accept_loop() {
    while (!stop_) {
      pollfd p{listen_fd_, POLLIN, 0};
      if (::poll(&p, 1, 20) <= 0) continue;
      const int client = ::accept(listen_fd_, nullptr, nullptr);
      if (client < 0) continue;
      const int upstream = connect_upstream();
      if (upstream < 0) {
        ::close(client);
        continue;
      }
      std::lock_guard lock(mu_);
      fds_.push_back(client);
      fds_.push_back(upstream);
      threads_.emplace_back([this, client, upstream] { pump(client, upstream, false); });
      threads_.emplace_back([this, client, upstream] { pump(upstream, client, true); });
    }
  }
  int connect_upstream() const {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(target_port_));
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      ::close(fd);
      return -1;
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    return fd;
  }
  /// Copies `from` to `to` until either side closes; answers (`trickle`) byte by byte while slowed.
  void pump(int from, int to, bool trickle) {
    char buf[512];
    for (;;) {
      const ssize_t n = ::recv(from, buf, sizeof buf, 0);
      if (n <= 0 || stop_) break;
      const int gap = trickle ? gap_ms_.load() : 0;
      bool ok = true;
      for (ssize_t i = 0; ok && i<n; i += gap> 0 ? 1 : n) {
        const std::size_t chunk = gap > 0 ? 1 : static_cast<std::size_t>(n);
        ok = ::send(to, buf + i, chunk, MSG_NOSIGNAL) == static_cast<ssize_t>(chunk);
        if (gap > 0) std::this_thread::sleep_for(std::chrono::milliseconds(gap));
        if (stop_) ok = false;
      }
      if (!ok) break;
    }
    // One side is gone: the other goes too (the driver reconnects through the proxy).
    ::shutdown(from, SHUT_RDWR);
    ::shutdown(to, SHUT_RDWR);
  }

  int target_port_;
  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> gap_ms_{0};
  std::mutex mu_;
  std::vector<int> fds_;              // closed at the end only, so that no number is reused while a pump runs
  std::vector<std::thread> threads_;  // the pumps
  std::thread accepting_;
};

}  // namespace tocd::acquisition::testing
