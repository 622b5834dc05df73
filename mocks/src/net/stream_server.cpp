// The event loop shared by the simulated instruments' TCP servers: one thread, poll() over
// non-blocking sockets, so that a slow, silent or greedy client only ever costs itself.
#include "net/stream_server.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <vector>

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"

namespace tocd::mocks::net {

namespace {

// One read() takes at most this much; a client gets at most `reads_per_wake` of them per turn
// of the loop, so that a client streaming bytes cannot starve the others.
constexpr std::size_t read_chunk = 16 * 1024;
constexpr int reads_per_wake = 4;
// Connections taken per turn, for the same reason.
constexpr int accepts_per_wake = 64;

struct Client {
  int fd = -1;
  std::unique_ptr<Session> session;
  std::string input;
  std::deque<Outgoing> out;
  std::size_t out_bytes = 0;  ///< queued and not yet sent
  std::size_t sent_of_front = 0;
  std::optional<Clock::time_point> request_started;  ///< first byte of the unfinished request
  Clock::time_point last_active;
  bool dead = false;
};

int ms_until(Clock::time_point t, Clock::time_point now) {
  const auto ms = std::chrono::ceil<std::chrono::milliseconds>(t - now).count();
  return static_cast<int>(std::clamp<long long>(ms, 0, 60'000));
}

}  // namespace

/// The loop's state, owned by the server thread.
struct StreamServer::Impl {
  StreamServer& s;
  std::vector<Client> clients;
  Clock::time_point accept_paused_until{};
  Clock::time_point last_accept_warning{};

  explicit Impl(StreamServer& server) : s(server) {}
  ~Impl() {
    for (auto& c : clients) ::close(c.fd);
  }

  void drop(Client& c, const char* why) {
    if (c.dead) return;
    if (why) logger("mocks")->debug("{}: closing a client: {}", s.name_, why);
    ::close(c.fd);
    c.dead = true;
  }

  void run() {
    std::vector<pollfd> fds;
    while (!s.stopping_) {
      const auto now = Clock::now();
      const bool accepting = now >= accept_paused_until;
      int wait_ms = accepting ? -1 : ms_until(accept_paused_until, now);
      const auto sooner = [&](Clock::time_point t) {
        const int ms = ms_until(t, now);
        wait_ms = wait_ms < 0 ? ms : std::min(wait_ms, ms);
      };
      fds.clear();
      fds.push_back({s.wake_fd_, POLLIN, 0});
      fds.push_back({accepting ? s.listen_fd_ : -1, POLLIN, 0});
      for (const auto& c : clients) {
        short events = POLLIN;
        if (!c.out.empty()) {
          if (c.out.front().ready <= now)
            events |= POLLOUT;
          else
            sooner(c.out.front().ready);
        }
        if (c.request_started) sooner(*c.request_started + s.limits_.request_deadline);
        fds.push_back({c.fd, events, 0});
      }
      if (::poll(fds.data(), fds.size(), wait_ms) < 0 && errno != EINTR) {
        logger("mocks")->error("{}: poll failed: {}", s.name_, std::strerror(errno));
        break;
      }
      if (fds[0].revents & POLLIN) {
        std::uint64_t n = 0;
        (void)!::read(s.wake_fd_, &n, sizeof n);
        if (s.drop_requested_.exchange(false))
          for (auto& c : clients) drop(c, nullptr);
      }
      // Clients accepted below are not in `fds` yet. Checking stopping_ per client: a flood of
      // requests on many connections cannot delay stop() by more than one client's share.
      const std::size_t polled = clients.size();
      for (std::size_t i = 0; i < polled && !s.stopping_; ++i) {
        if (clients[i].dead) continue;
        if (fds[i + 2].revents & (POLLIN | POLLHUP | POLLERR)) read_from(clients[i]);
        if (!clients[i].dead) write_to(clients[i]);
      }
      enforce_deadlines();
      std::erase_if(clients, [](const Client& c) { return c.dead; });
      if (fds[1].revents & POLLIN) accept_new();
    }
  }

  void accept_new() {
    for (int i = 0; i < accepts_per_wake; ++i) {
      const int fd = ::accept4(s.listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) {
        if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
          // The connection stays queued and the listener stays readable: without a pause the
          // loop would spin at full speed until a descriptor frees up.
          const auto now = Clock::now();
          accept_paused_until = now + s.limits_.accept_backoff;
          if (now - last_accept_warning > std::chrono::seconds(10)) {
            last_accept_warning = now;
            logger("mocks")->warn("{}: cannot accept a connection ({}); pausing accepts", s.name_,
                                  std::strerror(errno));
          }
        }
        return;  // EAGAIN: none left; anything else: the peer went away before we took it
      }
      const int one = 1;
      ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      if (static_cast<int>(clients.size()) >= s.limits_.max_clients) make_room();
      Client c;
      c.fd = fd;
      c.session = s.new_session_();
      c.last_active = Clock::now();
      clients.push_back(std::move(c));
      ++s.accepted_;
    }
  }

  /// At the connection limit, the connection silent longest gives way to the newcomer.
  void make_room() {
    auto oldest = std::min_element(clients.begin(), clients.end(), [](const Client& a, const Client& b) {
      return a.last_active < b.last_active;
    });
    drop(*oldest, "connection limit reached; it was the one silent longest");
    clients.erase(oldest);
  }

  void read_from(Client& c) {
    char buf[read_chunk];
    bool got = false;
    for (int i = 0; i < reads_per_wake; ++i) {
      const ssize_t n = ::recv(c.fd, buf, sizeof buf, MSG_DONTWAIT);
      if (n == 0) return drop(c, nullptr);  // the client closed
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) break;
        return drop(c, nullptr);  // reset by the peer
      }
      if (c.input.empty()) c.request_started = Clock::now();
      c.input.append(buf, static_cast<std::size_t>(n));
      got = true;
      if (static_cast<std::size_t>(n) < sizeof buf) break;
    }
    if (!got) return;
    c.last_active = Clock::now();
    const std::size_t before = c.input.size();
    const std::size_t queued = c.out.size();
    if (!c.session->consume(c.input, c.out)) return drop(c, "request refused by the protocol");
    for (std::size_t i = queued; i < c.out.size(); ++i) c.out_bytes += c.out[i].bytes.size();
    if (c.input.empty())
      c.request_started.reset();
    else if (c.input.size() < before)
      c.request_started = Clock::now();  // what is left is the start of the next request
    if (c.input.size() > s.limits_.max_request_bytes) return drop(c, "request longer than the limit");
    if (c.out_bytes > s.limits_.max_output_bytes) return drop(c, "too many answers left unread");
  }

  void write_to(Client& c) {
    const auto now = Clock::now();
    while (!c.out.empty() && c.out.front().ready <= now) {
      const std::string& b = c.out.front().bytes;
      const ssize_t n =
          ::send(c.fd, b.data() + c.sent_of_front, b.size() - c.sent_of_front, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return;  // POLLOUT next turn
        return drop(c, nullptr);
      }
      c.last_active = now;
      c.sent_of_front += static_cast<std::size_t>(n);
      c.out_bytes -= static_cast<std::size_t>(n);
      if (c.sent_of_front < b.size()) return;  // the socket is full
      c.out.pop_front();
      c.sent_of_front = 0;
    }
  }

  void enforce_deadlines() {
    const auto now = Clock::now();
    for (auto& c : clients)
      if (!c.dead && c.request_started && now - *c.request_started > s.limits_.request_deadline)
        drop(c, "request not complete within the deadline");
  }
};

StreamServer::StreamServer(std::string name, Listener listener, ServerLimits limits,
                           SessionFactory new_session)
    : name_(std::move(name)),
      listen_fd_(listener.fd),
      port_(listener.port),
      limits_(limits),
      new_session_(std::move(new_session)) {
  if (limits_.max_clients < 1 || limits_.max_request_bytes < 1 || limits_.max_output_bytes < 1 ||
      limits_.request_deadline.count() <= 0 || limits_.accept_backoff.count() <= 0) {
    ::close(listen_fd_);
    throw ConfigError(name_ +
                      ": server limits must be positive (connections, request and output bytes, deadline, "
                      "accept back-off)");
  }
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) {
    ::close(listen_fd_);
    throw Error(name_ + ": cannot create an eventfd: " + std::strerror(errno));
  }
  thread_ = std::thread([this] { Impl(*this).run(); });
}

StreamServer::~StreamServer() {
  stop();
  ::close(wake_fd_);
}

void StreamServer::wake() {
  const std::uint64_t one = 1;
  (void)!::write(wake_fd_, &one, sizeof one);
}

void StreamServer::stop() {
  stopping_ = true;
  if (thread_.joinable()) {
    wake();
    thread_.join();
  }
  if (listen_fd_ >= 0) ::close(listen_fd_);
  listen_fd_ = -1;
}

void StreamServer::drop_clients() {
  drop_requested_ = true;
  wake();
}

}  // namespace tocd::mocks::net
