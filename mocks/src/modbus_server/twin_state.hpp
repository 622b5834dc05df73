#pragma once

// What the Modbus twins (tester/tester_twin.cpp on TCP, vacuum/vacuum_twin.cpp on a serial
// line) hold alike: a physics on the shared clock, the register view of it, the registers, and
// the lock and fault queue that the server and the twin's hooks share.

#include <functional>
#include <memory>
#include <mutex>
#include <random>
#include <string_view>

#include <fmt/format.h>
#include <modbus/modbus.h>

#include "modbus_server/fault_queue.hpp"
#include "modbus_server/register_server.hpp"
#include "modbus_server/tcp_session.hpp"
#include "tocd/core/error.hpp"
#include "tocd/mocks/sim_clock.hpp"

namespace tocd::mocks {

/// The clock's simulated time in seconds, the time a physics advances to.
inline double sim_seconds(const SimClock& clock) {
  return static_cast<double>(clock.now_ns()) * 1e-9;
}

/// A RegisterDevice that publishes a physics (TesterPhysics, VacuumPhysics) as it is on the clock.
template <class Physics>
class PhysicsRegisters : public RegisterDevice {
 public:
  PhysicsRegisters(Physics& physics, const SimClock& clock) : physics_(physics), clock_(clock) {}

 protected:
  /// Brings the physics up to the clock's time (refresh() does, before it publishes).
  void advance_to_now() { physics_.advance(sim_seconds(clock_)); }

  Physics& physics_;

 private:
  const SimClock& clock_;
};

/// The state of one Modbus twin. `Registers` is its PhysicsRegisters<Physics>; the holding and
/// input registers are allocated here and freed with the state, after whatever serves them.
template <class Physics, class Registers>
struct TwinState {
  TwinState(const std::shared_ptr<const SimClock>& c, const typename Physics::Params& params,
            int holding_count, int input_count, std::string_view instrument)
      : clock(c ? c : std::make_shared<SimClock>(1.0)), physics(params), registers(physics, *clock) {
    map = modbus_mapping_new(0, 0, holding_count, input_count);
    if (!map) throw Error(fmt::format("{}: cannot allocate the registers", instrument));
  }
  ~TwinState() { modbus_mapping_free(map); }
  TwinState(const TwinState&) = delete;
  TwinState& operator=(const TwinState&) = delete;

  /// `f(physics)` under the state lock: a fault hook acting on the physics as it stands.
  template <class F>
  auto locked(F&& f) {
    std::lock_guard lock(state_mutex);
    return std::invoke(std::forward<F>(f), physics);
  }

  /// `f(physics)` under the state lock, the physics brought up to the clock's time first: what
  /// the twin reports of it.
  template <class F>
  auto at_now(F&& f) {
    std::lock_guard lock(state_mutex);
    physics.advance(sim_seconds(*clock));
    return std::invoke(std::forward<F>(f), physics);
  }

  /// What a server answers from, drawing its random faults from `rng`.
  RegisterServerState server_state(std::mt19937_64& rng) {
    return {*map, registers, state_mutex, faults, rng};
  }

  std::shared_ptr<const SimClock> clock;
  Physics physics;
  Registers registers;
  std::mutex state_mutex;
  FaultQueue faults;
  modbus_mapping_t* map = nullptr;
};

}  // namespace tocd::mocks
