// The simulated meter's SCPI-over-TCP server: one thread, poll() over the listening socket
// and every client; answers leave in order, each not before its ready time (delays).
#include <cerrno>
#include <cstring>
#include <deque>
#include <vector>

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "powermeter/twin_impl.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"

namespace tocd::mocks {
namespace {

struct Client {
  int fd = -1;
  std::string in;
  struct Out {
    std::string bytes;
    PowerMeterTwin::Impl::Clock::time_point ready;
  };
  std::deque<Out> out;
  PowerMeterTwin::Impl::Clock::time_point busy_until{};  ///< answers keep their order
};

}  // namespace

int PowerMeterTwin::Impl::start_tcp(const std::string& host, int port) {
  stop_tcp();
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* ai = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &ai) != 0 || !ai)
    throw ConfigError(fmt::format("simulated power meter: cannot resolve \"{}\"", host));
  const int fd = ::socket(ai->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (fd < 0 || ::bind(fd, ai->ai_addr, ai->ai_addrlen) != 0 || ::listen(fd, 8) != 0) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    ::freeaddrinfo(ai);
    throw ConfigError(fmt::format("simulated power meter: cannot listen on {}:{}: {}", host, port, why));
  }
  ::freeaddrinfo(ai);
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  {
    std::lock_guard lock(mutex);
    listen_fd = fd;
    tcp_host = host;
    tcp_port = ntohs(bound.sin_port);
  }
  stopping = false;
  server = std::thread([this] { serve_loop(); });
  return tcp_port;
}

void PowerMeterTwin::Impl::stop_tcp() {
  stopping = true;
  if (server.joinable()) server.join();
  if (listen_fd >= 0) ::close(listen_fd);
  listen_fd = -1;
}

void PowerMeterTwin::Impl::serve_loop() {
  std::vector<Client> clients;
  const auto close_client = [](Client& c) {
    ::close(c.fd);
    c.fd = -1;
  };
  while (!stopping) {
    std::vector<pollfd> fds{{listen_fd, POLLIN, 0}};
    int wait_ms = 20;  // also the latency of noticing stop_tcp()
    const auto now = Clock::now();
    for (const auto& c : clients) {
      fds.push_back({c.fd, static_cast<short>(POLLIN), 0});
      if (!c.out.empty()) {
        const auto ms =
            std::chrono::duration_cast<std::chrono::milliseconds>(c.out.front().ready - now).count();
        wait_ms = std::clamp<int>(static_cast<int>(ms), 0, wait_ms);
      }
    }
    if (::poll(fds.data(), fds.size(), wait_ms) < 0 && errno != EINTR) break;
    if (fds[0].revents & POLLIN) {
      const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC);
      if (fd >= 0) {
        clients.push_back(Client{fd, {}, {}, {}});
        std::lock_guard lock(mutex);
        ++stats.tcp_connections;
      }
    }
    for (std::size_t i = 1; i < fds.size(); ++i) {
      Client& c = clients[i - 1];
      if (!(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      char buf[4096];
      const ssize_t n = ::recv(c.fd, buf, sizeof buf, MSG_DONTWAIT);
      if (n <= 0) {
        if (n == 0 || (errno != EAGAIN && errno != EINTR)) close_client(c);
        continue;
      }
      c.in.append(buf, static_cast<std::size_t>(n));
      for (auto nl = c.in.find('\n'); nl != std::string::npos && c.fd >= 0; nl = c.in.find('\n')) {
        std::string line = c.in.substr(0, nl);
        c.in.erase(0, nl + 1);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        Reply r = handle(line);
        if (r.action == Action::drop) {
          close_client(c);
        } else if (r.action == Action::answer) {
          c.busy_until = std::max(c.busy_until, r.ready);
          c.out.push_back({r.bytes + "\n", c.busy_until});
        }
      }
    }
    const auto t = Clock::now();
    for (auto& c : clients) {
      while (c.fd >= 0 && !c.out.empty() && c.out.front().ready <= t) {
        const std::string& b = c.out.front().bytes;
        if (::send(c.fd, b.data(), b.size(), MSG_NOSIGNAL) < 0) close_client(c);
        c.out.pop_front();
      }
    }
    std::erase_if(clients, [](const Client& c) { return c.fd < 0; });
  }
  for (auto& c : clients) close_client(c);
  logger("mocks")->debug("simulated power meter: TCP server stopped");
}

}  // namespace tocd::mocks
