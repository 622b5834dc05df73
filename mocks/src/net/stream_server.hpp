#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "net/listener.hpp"
#include "tocd/mocks/server_limits.hpp"

namespace tocd::mocks::net {

using Clock = std::chrono::steady_clock;

/// One answer waiting for its client, not to be sent before `ready` (a simulated busy time).
struct Outgoing {
  std::string bytes;
  Clock::time_point ready;
};

/// The protocol side of one connection: cuts complete requests off the front of the input and
/// queues their answers. Called on the server thread only.
class Session {
 public:
  virtual ~Session() = default;
  /// Takes every complete request at the front of `input` (erasing it) and appends answers to
  /// `out` (sent in order, each not before its ready time). Returns false to close the
  /// connection (a framing error, or an injected fault).
  virtual bool consume(std::string& input, std::deque<Outgoing>& out) = 0;
};

/// A TCP server on one thread that no client can stall: non-blocking sockets under poll(),
/// per-client input and output buffers with caps, a connection limit, a per-request deadline,
/// back-off when accept() runs out of descriptors, and a wake-up descriptor so that stop()
/// returns at once whatever the clients do (docs/security.md).
class StreamServer {
 public:
  using SessionFactory = std::function<std::unique_ptr<Session>()>;
  /// Serves `listener` (whose descriptor it takes over) until stop() or destruction; `name`
  /// prefixes its log lines. `new_session` is called on the server thread for each connection.
  StreamServer(std::string name, Listener listener, ServerLimits limits, SessionFactory new_session);
  ~StreamServer();  ///< stop()
  StreamServer(const StreamServer&) = delete;
  StreamServer& operator=(const StreamServer&) = delete;

  int port() const { return port_; }
  /// Stops serving, closes every connection and the listening socket; returns once the thread
  /// has ended (promptly: the thread never blocks on a client).
  void stop();
  /// Closes every client connection (the listener stays); thread-safe.
  void drop_clients();
  long connections_accepted() const { return accepted_; }

 private:
  struct Impl;
  void wake();

  std::string name_;
  int listen_fd_ = -1, wake_fd_ = -1, port_ = 0;
  ServerLimits limits_;
  SessionFactory new_session_;
  std::atomic<bool> stopping_{false}, drop_requested_{false};
  std::atomic<long> accepted_{0};
  std::thread thread_;
};

}  // namespace tocd::mocks::net
