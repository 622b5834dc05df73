// The simulated vacuum controller: Modbus RTU server on the master side of a pseudo-terminal.
#include "tocd/mocks/vacuum_twin.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <fmt/format.h>
#include <modbus/modbus.h>
#include <pty.h>
#include <sys/select.h>
#include <termios.h>
#include <unistd.h>

#include "modbus_server/identity.hpp"
#include "modbus_server/register_server.hpp"
#include "modbus_server/twin_state.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/register_codec.hpp"
#include "tocd/devices/vacuum_registers.hpp"
#include "vacuum/vacuum_physics.hpp"

namespace tocd::mocks {

namespace vm = tocd::devices::vacuum_map;

namespace {

class VacuumRegisters final : public PhysicsRegisters<VacuumPhysics> {
 public:
  using PhysicsRegisters::PhysicsRegisters;

  void refresh(modbus_mapping_t& map) override {
    advance_to_now();
    std::uint16_t* in = map.tab_input_registers;
    put_float(in, vm::in_pressure, physics_.pressure_kPa());
    put_float(in, vm::in_setpoint, physics_.setpoint_kPa());
    std::uint16_t s = 0;
    if (physics_.pump_running()) s |= vm::st_pump_running;
    if (physics_.vent_open()) s |= vm::st_vent_open;
    if (physics_.at_setpoint()) s |= vm::st_at_setpoint;
    if (physics_.error_code() != 0) s |= vm::st_error;
    in[vm::in_status] = s;
    in[vm::in_error_code] = physics_.error_code();
    map.tab_registers[vm::hr_pump_run] = physics_.pump_running() ? 1 : 0;
  }

  int check_write(const modbus_mapping_t& map, int address, int count, const std::uint16_t* values) override {
    const WriteRange w{address, count};
    const std::vector<std::uint16_t> hr = holding_after_write(map, w, values);
    VacuumPhysics probe = physics_;
    if (w.touched_float(vm::hr_setpoint))
      if (const int e = probe.set_setpoint(get_float(hr.data(), vm::hr_setpoint))) return e;
    if (w.touched(vm::hr_pump_run)) {
      if (hr[vm::hr_pump_run] > 1) return 3;
      if (const int e = probe.run_pump(hr[vm::hr_pump_run] == 1)) return e;
    }
    if (w.touched(vm::hr_vent) && hr[vm::hr_vent] > 1) return 3;
    if (w.touched(vm::hr_clear_error) && hr[vm::hr_clear_error] > 1) return 3;
    return 0;
  }

  void after_write(modbus_mapping_t& map, int address, int count) override {
    const std::uint16_t* hr = map.tab_registers;
    const WriteRange w{address, count};
    if (w.touched_float(vm::hr_setpoint)) physics_.set_setpoint(get_float(hr, vm::hr_setpoint));
    if (w.touched(vm::hr_pump_run)) physics_.run_pump(hr[vm::hr_pump_run] == 1);
    if (w.touched(vm::hr_vent)) physics_.set_vent(hr[vm::hr_vent] == 1);
    if (w.touched(vm::hr_clear_error) && hr[vm::hr_clear_error] == 1) {
      physics_.clear_error();
      map.tab_registers[vm::hr_clear_error] = 0;
    }
    refresh(map);
  }
};

}  // namespace

struct VacuumTwin::Impl : TwinState<VacuumPhysics, VacuumRegisters> {
  VacuumTwinOptions opt;
  int master_fd = -1, slave_fd = -1;
  std::string path;
  modbus_t* ctx = nullptr;
  std::atomic<bool> stop{false};
  std::thread thread;
  std::mt19937_64 rng{7};
  std::mt19937_64 frame_rng{11};  // serve_frame's, apart from the server thread's

  explicit Impl(VacuumTwinOptions o)
      : TwinState(o.clock, o.physics, vm::holding_count, vm::input_count, "vacuum twin"), opt(std::move(o)) {
    if (opt.slave_id < 1 || opt.slave_id > 247)
      throw ConfigError(fmt::format("vacuum twin: slave id must be 1..247 (got {})", opt.slave_id));
    char name[128] = {};
    if (openpty(&master_fd, &slave_fd, name, nullptr, nullptr) != 0)
      throw Error(fmt::format("vacuum twin: cannot open a pseudo-terminal: {}", std::strerror(errno)));
    path = name;
    ::fcntl(master_fd, F_SETFL, ::fcntl(master_fd, F_GETFL) | O_NONBLOCK);
    termios t{};
    tcgetattr(slave_fd, &t);
    cfmakeraw(&t);  // bytes pass untouched, as on a real serial line
    tcsetattr(slave_fd, TCSANOW, &t);
    write_identity_block(map->tab_input_registers, vm::map_version, "tocdlab",
                         "simulated pump controller VC-1", "SIMVAC01", "1.0.0");
    put_float(map->tab_registers, vm::hr_setpoint, physics.setpoint_kPa());
    make_context();
    registers.refresh(*map);
    thread = std::thread([this] { serve(); });
  }

  /// libmodbus RTU expects, after a request for another slave, that slave's answer next; a
  /// fresh context forgets that, since on this line nobody else answers.
  void make_context() {
    if (ctx) modbus_free(ctx);
    ctx = modbus_new_rtu(path.c_str(), 19200, 'N', 8, 1);  // serial settings unused: the fd is given
    if (!ctx) throw Error("vacuum twin: cannot allocate the Modbus RTU server");
    modbus_set_slave(ctx, opt.slave_id);
    modbus_set_socket(ctx, master_fd);  // RS-232 mode: the RS-485 ioctl would fail on a pty
    modbus_set_byte_timeout(ctx, 0, 50000);
  }

  ~Impl() {
    stop = true;
    if (thread.joinable()) thread.join();
    modbus_free(ctx);
    ::close(master_fd);
    ::close(slave_fd);
  }

  void serve() {
    std::vector<std::uint8_t> req(MODBUS_RTU_MAX_ADU_LENGTH);
    while (!stop) {
      fd_set rd;
      FD_ZERO(&rd);
      FD_SET(master_fd, &rd);
      timeval tv{0, 10000};
      if (select(master_fd + 1, &rd, nullptr, nullptr, &tv) <= 0) continue;
      const int n = modbus_receive(ctx, req.data());
      if (n < 0) {  // bad CRC or a partial frame from the client: drop what is left
        modbus_flush(ctx);
        continue;
      }
      if (n == 0) {
        make_context();
        continue;
      }
      answer(serve_request(false, req.data(), n, *map, registers, state_mutex, faults, rng));
    }
  }

  /// Puts an answer on the line. A serial line never waits for its listener: bytes the
  /// client's side has no room for are lost, and the server goes on (the master is
  /// non-blocking), so a client that stops reading cannot stall the twin or its shutdown.
  void answer(const ModbusAnswer& a) {
    if (a.kind != ModbusAnswer::Kind::send) return;  // a dropped link is silence on a serial line
    if (a.delay_s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(a.delay_s));
    (void)!::write(master_fd, a.bytes.data(), a.bytes.size());
  }
};

VacuumTwin::VacuumTwin(VacuumTwinOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
VacuumTwin::~VacuumTwin() = default;

const std::string& VacuumTwin::device_path() const {
  return impl_->path;
}

devices::ModbusRtuAddress VacuumTwin::address() const {
  devices::ModbusRtuAddress a;
  a.device = impl_->path;
  a.slave_id = impl_->opt.slave_id;
  return a;
}

double VacuumTwin::pressure_kPa() const {
  return impl_->at_now(&VacuumPhysics::pressure_kPa);
}

void VacuumTwin::inject(const ModbusFault& fault) {
  impl_->faults.push(fault);
}

void VacuumTwin::inject_seal_loss(bool lost) {
  impl_->locked([lost](VacuumPhysics& p) { p.set_seal_lost(lost); });
}

int VacuumTwin::faults_pending() const {
  return impl_->faults.pending();
}

std::vector<std::uint8_t> VacuumTwin::serve_frame(std::span<const std::uint8_t> frame) {
  // What libmodbus' RTU receive lets through to the server: whole frames with a good CRC,
  // addressed to this slave (or broadcast).
  const std::size_t n = frame.size();
  if (n < 4 || n > MODBUS_RTU_MAX_ADU_LENGTH) return {};
  const std::uint16_t crc = modbus_crc16(frame.data(), n - 2);
  if (frame[n - 2] != (crc & 0xFF) || frame[n - 1] != (crc >> 8)) return {};
  if (frame[0] != impl_->opt.slave_id && frame[0] != MODBUS_BROADCAST_ADDRESS) return {};
  const ModbusAnswer a = serve_request(false, frame.data(), static_cast<int>(n), *impl_->map,
                                       impl_->registers, impl_->state_mutex, impl_->faults, impl_->frame_rng);
  if (a.kind != ModbusAnswer::Kind::send) return {};
  return a.bytes;
}

}  // namespace tocd::mocks
