#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "tocd/devices/power_meter_drivers.hpp"
#include "tocd/devices/usb_endpoint.hpp"
#include "tocd/mocks/server_limits.hpp"
#include "tocd/mocks/sim_clock.hpp"

namespace tocd::mocks {

/// What the simulated Thorlabs PM100-class meter is and what light reaches it.
struct PowerMeterTwinOptions {
  /// True optical power on the sensor (W), sampled at every reading. SimulatedLab passes
  /// source power x tissue transmission at the current pin displacement. Default: dark.
  /// Called from the server thread under the twin's lock: must not call back into the twin.
  std::function<double()> power_W;
  double noise_relative = 0.002;  ///< 1-sigma noise per sample, fraction of the power
  double noise_floor_W = 2e-10;   ///< 1-sigma noise per sample, absolute
  double dark_offset_W = 5e-9;    ///< what the sensor reads in the dark until zeroed
  double max_power_W = 0.5;       ///< sensor limit; above it the meter reports over-range
  /// Wavelength of the light (nm); when set, a reading at another correction wavelength is
  /// scaled by the ratio of (ideal silicon) responsivities, lambda_light / lambda_set.
  std::optional<double> light_wavelength_nm;
  double zero_duration_s = 0.4;   ///< simulated time a zeroing takes
  double sample_time_s = 0.0003;  ///< simulated time per averaged sample
  std::uint64_t seed = 1;
  std::shared_ptr<const SimClock> clock;  ///< null: a clock of its own, factor 1
  std::string model = "PM100USB", serial = "P0012345", firmware = "1.6.0";
  std::uint16_t usb_product_id = 0x8072;
  std::string sensor = "S121C,19012345,02-Feb-2024,1,18,289";
  /// What the SCPI TCP server grants each client; max_request_bytes caps the line length
  /// (docs/security.md).
  ServerLimits limits;
};

/// Counters of what the twin has seen (thread-safe snapshot).
struct PowerMeterTwinStats {
  long messages = 0;  ///< program messages received (TCP lines / USBTMC messages)
  long queries = 0;
  long tcp_connections = 0;
  long usb_opens = 0;
  long usb_rejected = 0;  ///< bulk-OUT transfers refused for bad framing
  std::string last_usb_rejection;
};

/// A simulated optical power meter: the SCPI engine (error queue, wavelength, averaging, range,
/// zero state, reading = light + dark offset - zero + noise) served over a loopback TCP
/// socket (SCPI, newline-terminated) and as in-process USBTMC endpoints that check every
/// bulk transfer byte for byte. Fault injection applies to whichever transport asks next.
/// Every public member is thread-safe.
class PowerMeterTwin {
 public:
  explicit PowerMeterTwin(PowerMeterTwinOptions options = {});
  ~PowerMeterTwin();  ///< stops the TCP server
  PowerMeterTwin(const PowerMeterTwin&) = delete;
  PowerMeterTwin& operator=(const PowerMeterTwin&) = delete;

  /// Starts the SCPI TCP server on `host`:`port` (0 = ephemeral); returns the bound port.
  int serve_tcp(const std::string& host = "127.0.0.1", int port = 0);
  void stop_tcp();
  devices::ScpiTcpAddress tcp_address() const;

  /// A fresh in-process USBTMC endpoint ("plugging the meter in"). An endpoint dies when a
  /// disconnect fault fires; a new one works again.
  std::unique_ptr<devices::UsbBulkEndpoint> open_usb_endpoint();
  /// Opener for devices::open_usbtmc_power_meter (null while usb_unplugged(true)).
  devices::UsbEndpointOpener usb_opener();
  void set_usb_unplugged(bool unplugged);

  // Fault injection: each applies to the next `count` program messages / answers.
  void delay_replies(int count, std::chrono::milliseconds delay);
  void swallow_replies(int count);      ///< queries get no answer at all (host times out)
  void garbage_replies(int count);      ///< the answer is replaced by non-text bytes
  void non_numeric_replies(int count);  ///< a numeric answer is replaced by text ("OVERLOAD")
  void over_range_readings(int count);  ///< power readings answer 9.9E37
  void drop_link(int count);            ///< TCP: close the connection; USB: the device vanishes
  void push_error(int code, const std::string& message);  ///< adds an SCPI error queue entry
  void usb_wrong_tag(int count);                          ///< DEV_DEP_MSG_IN echoes a wrong bTag
  void usb_short_header(int count);                       ///< DEV_DEP_MSG_IN transfer cut inside its header
  void clear_faults();

  /// Simulated state, for tests.
  double wavelength_nm() const;
  int averaging() const;
  bool auto_range() const;
  PowerMeterTwinStats stats() const;

  class Impl;

 private:
  std::shared_ptr<Impl> impl_;  // shared with the server thread and the USB endpoints
};

}  // namespace tocd::mocks
