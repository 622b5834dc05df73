// The simulated meter's SCPI-over-TCP server: newline-terminated program messages on a
// net::StreamServer; answers leave in order, each not before its ready time (busy times and
// injected delays).
#include <algorithm>
#include <string_view>

#include "net/line_scanner.hpp"
#include "net/stream_server.hpp"
#include "powermeter/twin_impl.hpp"
#include "tocd/core/log.hpp"

namespace tocd::mocks {
namespace {

/// One SCPI connection: each newline-terminated line is one program message. The line length
/// is capped by ServerLimits::max_request_bytes (the server drops a client past it).
class ScpiLineSession final : public net::Session {
 public:
  explicit ScpiLineSession(PowerMeterTwin::Impl& meter) : meter_(meter) {}

  bool consume(std::string& input, std::deque<net::Outgoing>& out) override {
    using Action = PowerMeterTwin::Impl::Action;
    return lines_.take_lines(input, [&](std::string_view line) {
      const auto r = meter_.handle(line);
      if (r.action == Action::answer) {
        busy_until_ = std::max(busy_until_, r.ready);  // answers keep their order
        out.push_back({r.bytes + "\n", busy_until_});
      }
      return r.action != Action::drop;
    });
  }

 private:
  PowerMeterTwin::Impl& meter_;
  net::LineScanner lines_;
  net::Clock::time_point busy_until_{};
};

}  // namespace

std::unique_ptr<net::Session> make_scpi_line_session(PowerMeterTwin::Impl& meter) {
  return std::make_unique<ScpiLineSession>(meter);
}

int PowerMeterTwin::Impl::start_tcp(const std::string& host, int port) {
  stop_tcp();
  auto listener = net::listen_tcp(host, port, "simulated power meter");
  const int bound = listener.port;
  auto s = std::make_unique<net::StreamServer>("simulated power meter", listener, options.limits, [this] {
    {
      std::lock_guard lock(mutex);
      ++stats.tcp_connections;
    }
    return make_scpi_line_session(*this);
  });
  std::lock_guard lock(mutex);
  tcp_host = host;
  tcp_port = bound;
  server = std::move(s);
  return bound;
}

void PowerMeterTwin::Impl::stop_tcp() {
  std::unique_ptr<net::StreamServer> s;
  {
    std::lock_guard lock(mutex);
    s = std::move(server);
  }
  if (!s) return;
  s->stop();  // outside the lock: the server thread takes it for every message
  logger("mocks")->debug("simulated power meter: TCP server stopped");
}

}  // namespace tocd::mocks
