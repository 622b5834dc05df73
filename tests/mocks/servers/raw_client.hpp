#pragma once

// A plain loopback TCP client for poking the simulated instruments' servers byte by byte, the
// way a misbehaving client would.
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace servertest {

using namespace std::chrono_literals;

class RawClient {
 public:
  /// Connects to 127.0.0.1:`port`; `receive_buffer` > 0 shrinks the socket's receive buffer
  /// (set before connecting, so that a client that never reads fills up quickly).
  explicit RawClient(int port, int receive_buffer = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (receive_buffer > 0) ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    const int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }
  ~RawClient() { ::close(fd_); }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool connected() const { return connected_; }
  int fd() const { return fd_; }

  /// Sends everything unless the connection fails, or the peer stops reading for `timeout`.
  bool send_all(std::string_view bytes, std::chrono::milliseconds timeout = 2000ms) {
    while (!bytes.empty()) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
      const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
  }

  /// Exactly `n` bytes, or nothing when the connection ends or `timeout` passes first.
  std::optional<std::string> read_exact(std::size_t n, std::chrono::milliseconds timeout = 2000ms) {
    std::string out;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (out.size() < n) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      pollfd p{fd_, POLLIN, 0};
      if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) return std::nullopt;
      char buf[4096];
      const ssize_t got = ::recv(fd_, buf, std::min(sizeof buf, n - out.size()), 0);
      if (got <= 0) return std::nullopt;
      out.append(buf, static_cast<std::size_t>(got));
    }
    return out;
  }

  /// One line (without its newline), or nothing.
  std::optional<std::string> read_line(std::chrono::milliseconds timeout = 2000ms) {
    std::string line;
    for (;;) {
      auto c = read_exact(1, timeout);
      if (!c) return std::nullopt;
      if ((*c)[0] == '\n') return line;
      line += *c;
    }
  }

  /// True when the server closes the connection (EOF or reset) within `within`; bytes that
  /// arrive in the meantime are read and ignored.
  bool closed_by_peer(std::chrono::milliseconds within) {
    const auto deadline = std::chrono::steady_clock::now() + within;
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      char buf[4096];
      const ssize_t got = ::recv(fd_, buf, sizeof buf, MSG_DONTWAIT);
      if (got == 0 || (got < 0 && errno != EAGAIN && errno != EINTR)) return true;
    }
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
};

/// A Modbus TCP request ADU: MBAP header (transaction id 1, protocol 0, unit 1) and `pdu`.
inline std::string modbus_adu(const std::vector<std::uint8_t>& pdu, std::uint16_t transaction = 1) {
  std::string a;
  a += static_cast<char>(transaction >> 8);
  a += static_cast<char>(transaction & 0xFF);
  a += '\0';
  a += '\0';
  const auto length = static_cast<std::uint16_t>(pdu.size() + 1);
  a += static_cast<char>(length >> 8);
  a += static_cast<char>(length & 0xFF);
  a += '\1';
  for (auto b : pdu) a += static_cast<char>(b);
  return a;
}

/// Sends `pdu` and returns the answer's PDU (nothing on timeout or a closed connection).
inline std::optional<std::vector<std::uint8_t>> modbus_call(RawClient& c,
                                                            const std::vector<std::uint8_t>& pdu) {
  if (!c.send_all(modbus_adu(pdu))) return std::nullopt;
  const auto header = c.read_exact(7);
  if (!header) return std::nullopt;
  const int length = (static_cast<std::uint8_t>((*header)[4]) << 8) | static_cast<std::uint8_t>((*header)[5]);
  const auto body = c.read_exact(static_cast<std::size_t>(length - 1));
  if (!body) return std::nullopt;
  return std::vector<std::uint8_t>(body->begin(), body->end());
}

}  // namespace servertest
