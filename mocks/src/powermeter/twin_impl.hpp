#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <string>

#include "net/stream_server.hpp"
#include "powermeter/scpi_meter_engine.hpp"
#include "tocd/mocks/power_meter_twin.hpp"

namespace tocd::mocks {

/// Shared state of one simulated meter: the engine, the fault counters and the TCP server.
/// Transports call handle() with each complete program message.
class PowerMeterTwin::Impl {
 public:
  using Clock = std::chrono::steady_clock;
  explicit Impl(PowerMeterTwinOptions options);
  ~Impl();

  enum class Action { none, answer, drop };
  struct Reply {
    Action action = Action::none;
    std::string bytes;        ///< answer without terminator (may be garbage on purpose)
    Clock::time_point ready;  ///< not to be sent before this
  };
  Reply handle(std::string_view message);

  enum class UsbFault { none, wrong_tag, short_header };
  UsbFault take_usb_fault();
  void note_usb_rejection(const std::string& why);

  // TCP server (scpi_tcp_server.cpp)
  int start_tcp(const std::string& host, int port);
  void stop_tcp();

  mutable std::mutex mutex;
  PowerMeterTwinOptions options;
  std::shared_ptr<const SimClock> clock;
  detail::ScpiMeterEngine engine;
  PowerMeterTwinStats stats;
  bool usb_unplugged = false;

  /// The injected faults: each counter is how many more program messages (or USB transfers)
  /// it applies to (PowerMeterTwin's fault hooks).
  struct Faults {
    int delayed = 0;
    std::chrono::milliseconds delay{0};
    int swallow = 0, garbage = 0, non_numeric = 0, drop = 0, wrong_tag = 0, short_header = 0;
  };
  Faults faults;
  /// Sets one counter of `faults` under the lock.
  void arm(int Faults::*counter, int count) {
    std::lock_guard lock(mutex);
    faults.*counter = count;
  }

  std::string tcp_host;
  int tcp_port = 0;
  std::unique_ptr<net::StreamServer> server;  ///< guarded by `mutex`
};

/// The SCPI line protocol of one TCP connection to `meter` (scpi_tcp_server.cpp).
std::unique_ptr<net::Session> make_scpi_line_session(PowerMeterTwin::Impl& meter);

}  // namespace tocd::mocks
