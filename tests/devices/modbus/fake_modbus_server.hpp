#pragma once
// A minimal Modbus TCP server for link tests: answers "read input registers" (function 4)
// from a fixed table, on IPv4 or IPv6 loopback, optionally one byte at a time with a gap
// between bytes (an instrument that trickles its answer).
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

class FakeModbusServer {
 public:
  struct Options {
    int family = AF_INET;                   ///< AF_INET (127.0.0.1) or AF_INET6 (::1)
    std::chrono::milliseconds byte_gap{0};  ///< 0: whole answers; else one byte per gap
    std::vector<std::uint16_t> input_registers = std::vector<std::uint16_t>(148, 0);
  };

  explicit FakeModbusServer(Options o) : o_(std::move(o)) {
    listen_fd_ = ::socket(o_.family, SOCK_STREAM, 0);
    if (listen_fd_ < 0) throw std::runtime_error("socket failed");
    const int one = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    int rc = -1;
    if (o_.family == AF_INET6) {
      sockaddr_in6 a{};
      a.sin6_family = AF_INET6;
      a.sin6_addr = in6addr_loopback;
      rc = ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    } else {
      sockaddr_in a{};
      a.sin_family = AF_INET;
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      rc = ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    }
    if (rc != 0 || ::listen(listen_fd_, 4) != 0) {
      ::close(listen_fd_);
      throw std::runtime_error("bind/listen on loopback failed");
    }
    sockaddr_storage bound{};
    socklen_t len = sizeof bound;
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&bound), &len);
    port_ = ntohs(o_.family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                        : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    thread_ = std::thread([this] { serve(); });
  }

  ~FakeModbusServer() {
    stop_ = true;
    thread_.join();
    ::close(listen_fd_);
  }

  int port() const { return port_; }

 private:
  // Waits until fd is readable, or false once the server stops.
  bool wait_readable(int fd) {
    while (!stop_) {
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 20) > 0) return true;
    }
    return false;
  }

  bool read_exact(int fd, std::uint8_t* buf, std::size_t n) {
    for (std::size_t got = 0; got < n;) {
      if (!wait_readable(fd)) return false;
      const ssize_t r = ::recv(fd, buf + got, n - got, 0);
      if (r <= 0) return false;
      got += static_cast<std::size_t>(r);
    }
    return true;
  }

  void serve() {
    while (wait_readable(listen_fd_)) {
      const int fd = ::accept(listen_fd_, nullptr, nullptr);
      if (fd < 0) continue;
      serve_client(fd);
      ::close(fd);
    }
  }

  void serve_client(int fd) {
    std::array<std::uint8_t, 12> req{};  // MBAP (7) + function, address, count
    while (read_exact(fd, req.data(), req.size())) {
      const int address = req[8] << 8 | req[9];
      const int count = req[10] << 8 | req[11];
      std::vector<std::uint8_t> answer{req[0], req[1], 0, 0, 0, 0, req[6], req[7]};
      if (req[7] != 4 || address + count > static_cast<int>(o_.input_registers.size())) {
        answer[7] = static_cast<std::uint8_t>(req[7] | 0x80);
        answer.push_back(2);  // illegal data address
      } else {
        answer.push_back(static_cast<std::uint8_t>(2 * count));
        for (int i = 0; i < count; ++i) {
          answer.push_back(static_cast<std::uint8_t>(o_.input_registers[address + i] >> 8));
          answer.push_back(static_cast<std::uint8_t>(o_.input_registers[address + i] & 0xFF));
        }
      }
      const std::size_t length = answer.size() - 6;
      answer[4] = static_cast<std::uint8_t>(length >> 8);
      answer[5] = static_cast<std::uint8_t>(length & 0xFF);
      if (o_.byte_gap.count() == 0) {
        if (::send(fd, answer.data(), answer.size(), MSG_NOSIGNAL) < 0) return;
        continue;
      }
      for (const std::uint8_t b : answer) {
        if (stop_ || ::send(fd, &b, 1, MSG_NOSIGNAL) < 0) return;
        std::this_thread::sleep_for(o_.byte_gap);
      }
    }
  }

  Options o_;
  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};
