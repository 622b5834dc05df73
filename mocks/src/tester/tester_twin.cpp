// The simulated mechanical tester: a Modbus TCP server (net::StreamServer) on its own thread.
#include "tocd/mocks/tester_twin.hpp"

#include <cmath>
#include <deque>
#include <vector>

#include <fmt/format.h>
#include <modbus/modbus.h>

#include "modbus_server/identity.hpp"
#include "modbus_server/tcp_session.hpp"
#include "modbus_server/twin_state.hpp"
#include "net/stream_server.hpp"
#include "tester/tester_physics.hpp"
#include "tocd/core/log.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/tester_registers.hpp"

namespace tocd::mocks {

namespace m = tocd::devices::tester_map;

namespace {

/// The register view of TesterPhysics.
class TesterRegisters final : public PhysicsRegisters<TesterPhysics> {
 public:
  using PhysicsRegisters::PhysicsRegisters;

  void refresh(modbus_mapping_t& map) override {
    advance_to_now();
    std::uint16_t* in = map.tab_input_registers;
    put_float(in, m::in_position, physics_.position_mm());
    put_float(in, m::in_load, physics_.measured_load_N());
    std::uint16_t s = m::st_homed;
    if (physics_.fault_code() == 0) s |= m::st_ready;
    if (physics_.moving()) s |= m::st_moving;
    if (physics_.at_target()) s |= m::st_at_target;
    if (physics_.limit()) s |= m::st_limit;
    if (physics_.fault_code() != 0) s |= m::st_fault;
    in[m::in_status] = s;
    in[m::in_fault_code] = physics_.fault_code();
  }

  int check_write(const modbus_mapping_t& map, int address, int count, const std::uint16_t* values) override {
    // What the holding registers would hold after the write.
    const WriteRange w{address, count};
    const std::vector<std::uint16_t> hr = holding_after_write(map, w, values);
    if (w.touched_float(m::hr_max_travel) || w.touched_float(m::hr_max_load)) {
      const float travel = get_float(hr.data(), m::hr_max_travel);
      const float load = get_float(hr.data(), m::hr_max_load);
      if (!physics_.limits_acceptable(travel, load)) return 3;
    }
    if (!w.touched(m::hr_command)) return 0;
    const std::uint16_t cmd = hr[m::hr_command];
    if (cmd > m::cmd_clear_fault) return 3;
    if (cmd == m::cmd_move) {
      // Validated here so that a refused move answers an exception and changes nothing.
      TesterPhysics probe = physics_;
      return probe.move(get_float(hr.data(), m::hr_target), get_float(hr.data(), m::hr_velocity));
    }
    if (cmd == m::cmd_home) {
      TesterPhysics probe = physics_;
      return probe.home();
    }
    return 0;
  }

  void after_write(modbus_mapping_t& map, int address, int count) override {
    std::uint16_t* hr = map.tab_registers;
    const WriteRange w{address, count};
    if (w.touched_float(m::hr_max_travel) || w.touched_float(m::hr_max_load))
      physics_.set_limits(get_float(hr, m::hr_max_travel), get_float(hr, m::hr_max_load));
    if (!w.touched(m::hr_command)) return;
    switch (hr[m::hr_command]) {
      case m::cmd_move:
        physics_.move(get_float(hr, m::hr_target), get_float(hr, m::hr_velocity));
        break;
      case m::cmd_stop:
        physics_.stop();
        break;
      case m::cmd_home:
        physics_.home();
        break;
      case m::cmd_tare:
        physics_.tare();
        break;
      case m::cmd_clear_fault:
        physics_.clear_fault();
        break;
      default:
        break;
    }
    hr[m::hr_command] = m::cmd_none;  // reads back 0 once accepted
    refresh(map);
  }
};

}  // namespace

struct TesterTwin::Impl : TwinState<TesterPhysics, TesterRegisters> {
  TesterTwinOptions opt;
  std::mt19937_64 rng;
  std::mt19937_64 stream_rng{0x5EED};         // serve_stream's, apart from the server thread's
  std::unique_ptr<net::StreamServer> server;  // last: stopped before the state it serves goes

  explicit Impl(TesterTwinOptions o)
      : TwinState(o.clock, o.physics, m::holding_count, m::input_count, "mechanical tester twin"),
        opt(std::move(o)),
        rng(opt.physics.seed ^ 0x9E3779B97F4A7C15ull) {
    write_identity_block(map->tab_input_registers, m::map_version, "tocdlab", "simulated load frame LF-1",
                         fmt::format("SIM{:05d}", static_cast<int>(opt.physics.seed % 100000)), "1.0.0");
    put_float(map->tab_registers, m::hr_velocity, 1.0);
    put_float(map->tab_registers, m::hr_max_travel, opt.physics.max_travel_mm);
    put_float(map->tab_registers, m::hr_max_load, opt.physics.max_load_N);
    registers.refresh(*map);
    server = std::make_unique<net::StreamServer>(
        "mechanical tester twin", net::listen_tcp(opt.host, opt.port, "mechanical tester twin"), opt.limits,
        [state = server_state(rng)] { return make_modbus_tcp_session(state); });
  }
};

TesterTwin::TesterTwin(TesterTwinOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  tocd::logger("mocks")->debug("mechanical tester twin on {}:{}", impl_->opt.host, impl_->server->port());
}

TesterTwin::~TesterTwin() = default;

int TesterTwin::port() const {
  return impl_->server->port();
}

devices::ModbusTcpAddress TesterTwin::address() const {
  return {impl_->opt.host, impl_->server->port(), impl_->opt.slave_id};
}

double TesterTwin::position_mm() const {
  return impl_->at_now(&TesterPhysics::position_mm);
}

double TesterTwin::displacement_mm() const {
  return impl_->at_now(&TesterPhysics::displacement_mm);
}

double TesterTwin::drained_displacement_mm() const {
  return impl_->at_now(&TesterPhysics::drained_displacement_mm);
}

void TesterTwin::inject(const ModbusFault& fault) {
  impl_->faults.push(fault);
}

void TesterTwin::drop_connections() {
  impl_->server->drop_clients();
}

void TesterTwin::trip_load_limit() {
  impl_->locked(&TesterPhysics::trip_load_limit);
}

void TesterTwin::set_drive_fault(std::uint16_t code) {
  impl_->locked([code](TesterPhysics& p) { p.set_drive_fault(code); });
}

int TesterTwin::connections_accepted() const {
  return static_cast<int>(impl_->server->connections_accepted());
}
int TesterTwin::faults_pending() const {
  return impl_->faults.pending();
}

TesterTwin::StreamReply TesterTwin::serve_stream(std::string_view received) {
  const auto session = make_modbus_tcp_session(impl_->server_state(impl_->stream_rng));
  std::string input(received);
  std::deque<net::Outgoing> out;
  StreamReply reply;
  reply.closed = !session->consume(input, out);
  for (const auto& o : out) reply.sent += o.bytes;
  return reply;
}

}  // namespace tocd::mocks
