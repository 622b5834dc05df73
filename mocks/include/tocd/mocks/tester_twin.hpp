#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "tocd/devices/modbus_options.hpp"
#include "tocd/mocks/modbus_faults.hpp"
#include "tocd/mocks/server_limits.hpp"
#include "tocd/mocks/tissue.hpp"

namespace tocd::mocks {

class SimClock;

/// The load frame and the sample under its pin, as the twin's physics simulates them
/// (mocks/src/tester/tester_physics.hpp). One struct for the twin's options and the physics, so
/// that every setting reaches the physics without a copy to keep in step.
struct TesterTwinPhysics {
  std::shared_ptr<TissueModel> tissue;  ///< default: make_analytic_tissue(2.5)
  double contact_position_mm = 1.0;     ///< pin touches the sample surface here
  double max_travel_mm = 10.0;
  double max_load_N = 50.0;
  /// The frame's stroke and the load cell's capacity: no limit can be set beyond them.
  double travel_range_mm = 100.0;
  double load_capacity_N = 500.0;
  double load_noise_N = 0.002;       ///< load-cell noise (1 sigma)
  double load_cell_offset_N = 0.05;  ///< what the cell reads unloaded before a tare
  double relaxation_fraction = 0.3;  ///< extra stress carried while moving (standard linear solid)
  double relaxation_time_s = 20.0;   ///< time constant of stress relaxation while holding
  /// Time constant of the drained displacement (first-order drainage; the simulated lab's
  /// delayed clearing follows it).
  double drained_time_s = 20.0;
  double max_velocity_mm_per_s = 20.0;
  double home_velocity_mm_per_s = 5.0;
  std::uint64_t seed = 1;  ///< the load-cell noise's; the twin's serial number and fault draws too
};

struct TesterTwinOptions {
  std::shared_ptr<const SimClock> clock;  ///< default: a real-time clock
  std::string host = "127.0.0.1";
  int port = 0;  ///< 0 = any free port (see TesterTwin::port())
  int slave_id = 1;
  TesterTwinPhysics physics;
  ServerLimits limits;  ///< what the Modbus TCP server grants each client (docs/security.md)
};

/// The simulated mechanical tester: a Modbus TCP server on its own thread, serving
/// the register map of docs/instruments/mechanical-tester.md, with finite-speed motion, load
/// from the tissue model plus relaxation and noise, load-limit trips and fault injection.
/// Thread-safe: the hooks may be called from any thread while clients talk to it.
class TesterTwin {
 public:
  explicit TesterTwin(TesterTwinOptions options = {});
  ~TesterTwin();  ///< stops the server
  TesterTwin(const TesterTwin&) = delete;
  TesterTwin& operator=(const TesterTwin&) = delete;

  int port() const;
  devices::ModbusTcpAddress address() const;

  /// Current pin position (mm) and displacement into the sample (mm, >= 0).
  double position_mm() const;
  double displacement_mm() const;
  /// The displacement whose water content the sample has reached: it follows displacement_mm()
  /// with physics.drained_time_s (first-order drainage, docs/instruments/simulated-lab.md).
  double drained_displacement_mm() const;

  // Fault hooks.
  void inject(const ModbusFault& fault);
  void drop_connections();                   ///< closes every client connection now
  void trip_load_limit();                    ///< as if the load exceeded the limit
  void set_drive_fault(std::uint16_t code);  ///< latches a fault with this code (clear_fault resets)
  int connections_accepted() const;
  int faults_pending() const;

  /// What the server does with `received` arriving on a fresh connection, without the network.
  struct StreamReply {
    std::string sent;     ///< the answers, in order
    bool closed = false;  ///< the server would close the connection (not Modbus TCP, or a fault)
  };
  /// Serves `received` as the bytes of one Modbus TCP connection: the server's own MBAP
  /// framing and request handling, on the caller's thread (for the fuzz targets and tests).
  /// An incomplete last frame is left unanswered. Not to be called from two threads at once.
  StreamReply serve_stream(std::string_view received);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tocd::mocks
