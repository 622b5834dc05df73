#include "modbus/modbus_link.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <modbus/modbus.h>
#include <netdb.h>
#include <sys/socket.h>

#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"
#include "tocd/devices/errors.hpp"
#include "trace.hpp"

namespace tocd::devices {
namespace {

// Registers as the big-endian bytes they travel as, for the trace.
std::vector<std::uint8_t> register_bytes(const std::uint16_t* regs, int count) {
  std::vector<std::uint8_t> b;
  b.reserve(static_cast<std::size_t>(2 * std::max(count, 0)));
  for (int i = 0; i < count; ++i) {
    b.push_back(static_cast<std::uint8_t>(regs[i] >> 8));
    b.push_back(static_cast<std::uint8_t>(regs[i] & 0xff));
  }
  return b;
}

const char* exception_name(int code) {
  switch (code) {
    case MODBUS_EXCEPTION_ILLEGAL_FUNCTION:
      return "illegal function";
    case MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS:
      return "illegal data address";
    case MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE:
      return "illegal data value";
    case MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE:
      return "slave device failure";
    case MODBUS_EXCEPTION_ACKNOWLEDGE:
      return "acknowledge";
    case MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY:
      return "slave device busy";
    case MODBUS_EXCEPTION_NEGATIVE_ACKNOWLEDGE:
      return "negative acknowledge";
    case MODBUS_EXCEPTION_MEMORY_PARITY:
      return "memory parity error";
    case MODBUS_EXCEPTION_GATEWAY_PATH:
      return "gateway path unavailable";
    case MODBUS_EXCEPTION_GATEWAY_TARGET:
      return "gateway target failed to respond";
    default:
      return "unknown exception";
  }
}

void set_timeout(modbus_t* ctx, double seconds, bool byte_timeout) {
  const double s = std::max(seconds, 0.001);
  const auto sec = static_cast<std::uint32_t>(std::floor(s));
  const auto usec = static_cast<std::uint32_t>((s - sec) * 1e6);
  if (byte_timeout)
    modbus_set_byte_timeout(ctx, sec, usec);
  else
    modbus_set_response_timeout(ctx, sec, usec);
}

void validate(const std::string& instrument, const ModbusOptions& o) {
  if (!(o.timeout_s > 0.0) || !std::isfinite(o.timeout_s) || o.retries < 0 || o.retries > 20 ||
      !(o.backoff_s >= 0.0) || !std::isfinite(o.backoff_s))
    throw ConfigError(
        fmt::format("{}: link options need timeout_s > 0, retries in 0..20, backoff_s >= 0 "
                    "(got {}, {}, {})",
                    instrument, o.timeout_s, o.retries, o.backoff_s));
}

}  // namespace

std::string register_operation(std::string_view verb, std::string_view table, int address, int count,
                               std::string_view what) {
  if (count == 1) return fmt::format("{} of {} register {} ({})", verb, table, address, what);
  return fmt::format("{} of {} registers {}..{} ({})", verb, table, address, address + count - 1, what);
}

ModbusLink::ModbusLink(std::string instrument, const Tcp& tcp, const ModbusOptions& options)
    : instrument_(std::move(instrument)), options_(options), tcp_(true) {
  validate(instrument_, options_);
  const auto& a = tcp.address;
  if (a.port <= 0 || a.port > 65535 || a.slave_id < 0 || a.slave_id > 255)
    throw ConfigError(fmt::format("{}: port must be 1..65535 and slave_id 0..255 (got {}, {})", instrument_,
                                  a.port, a.slave_id));
  // A host name, an IPv4 or an IPv6 address: the protocol-independent context resolves it on
  // each connect and tries every address it finds (modbus_new_tcp takes IPv4 literals only).
  if (a.host.empty() || a.host.size() > 253)
    throw ConfigError(fmt::format("{}: host must be a name or address of 1..253 characters (got \"{}\")",
                                  instrument_, a.host));
  host_ = a.host;
  service_ = std::to_string(a.port);
  ctx_ = modbus_new_tcp_pi(host_.c_str(), service_.c_str());
  if (!ctx_)
    throw ConfigError(fmt::format("{}: cannot make a Modbus TCP context for {}", instrument_, a.host));
  modbus_set_slave(ctx_, a.slave_id);
  set_timeout(ctx_, options_.timeout_s, false);
  // The AnswerDeadline bounds the whole answer; a shorter per-byte limit would only fail
  // answers that arrive in time but in pieces (a 100 ms stall of a busy machine did).
  set_timeout(ctx_, options_.timeout_s, true);
  modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE);
}

ModbusLink::ModbusLink(std::string instrument, const Rtu& rtu, const ModbusOptions& options)
    : instrument_(std::move(instrument)), options_(options), tcp_(false) {
  validate(instrument_, options_);
  const auto& a = rtu.address;
  if (a.device.empty()) throw ConfigError(fmt::format("{}: no serial device given", instrument_));
  if (a.parity != 'N' && a.parity != 'E' && a.parity != 'O')
    throw ConfigError(fmt::format("{}: parity must be N, E or O (got '{}')", instrument_, a.parity));
  if (a.data_bits < 5 || a.data_bits > 8 || (a.stop_bits != 1 && a.stop_bits != 2) || a.baud <= 0)
    throw ConfigError(fmt::format("{}: bad serial settings {} baud, {} data bits, {} stop bits", instrument_,
                                  a.baud, a.data_bits, a.stop_bits));
  if (a.slave_id < 1 || a.slave_id > 247)
    throw ConfigError(fmt::format("{}: RTU slave_id must be 1..247 (got {})", instrument_, a.slave_id));
  ctx_ = modbus_new_rtu(a.device.c_str(), a.baud, a.parity, a.data_bits, a.stop_bits);
  if (!ctx_)
    throw ConfigError(fmt::format("{}: cannot make a Modbus RTU context for {} ({})", instrument_, a.device,
                                  modbus_strerror(errno)));
  modbus_set_slave(ctx_, a.slave_id);
  set_timeout(ctx_, options_.timeout_s, false);
  set_timeout(ctx_, std::min(options_.timeout_s, 0.05), true);
  modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE);
}

ModbusLink::~ModbusLink() {
  if (ctx_) {
    drop();
    modbus_free(ctx_);
  }
}

void ModbusLink::drop() {
  if (connected_) modbus_close(ctx_);
  connected_ = false;
}

namespace {

// Why a host name does not resolve, or "" when it does. libmodbus reports a failed lookup as
// "Connection refused", which sends people looking for the wrong fault.
std::string resolution_failure(const std::string& host, const std::string& service) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* list = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &list);
  if (list) ::freeaddrinfo(list);
  return rc == 0 ? std::string{} : fmt::format("cannot resolve host \"{}\": {}", host, ::gai_strerror(rc));
}

}  // namespace

bool ModbusLink::connect_once(std::string& why) {
  // Not "== -1": the TCP PI backend returns getaddrinfo's (negative) code when a name does
  // not resolve, which would otherwise pass for a connection.
  if (modbus_connect(ctx_) != 0) {
    why = modbus_strerror(errno);
    modbus_close(ctx_);  // libmodbus leaves the socket/fd to us on failure
    if (tcp_) {
      if (std::string lookup = resolution_failure(host_, service_); !lookup.empty()) why = std::move(lookup);
    }
    return false;
  }
  if (ever_connected_) ++reconnects_;
  if (ever_connected_) tocd::logger("devices")->info("{}: reconnected", instrument_);
  connected_ = ever_connected_ = true;
  return true;
}

void ModbusLink::open() {
  transact("connect", [](_modbus*) { return 0; });
}

void ModbusLink::transact(const std::string& operation, const std::function<int(_modbus*)>& call) {
  enum class Kind { timeout, connection, protocol };
  Kind last_kind = Kind::connection;
  std::string last_why;
  for (int attempt = 0; attempt <= options_.retries; ++attempt) {
    if (attempt > 0) {
      const double wait = std::min(1.0, options_.backoff_s * std::pow(2.0, attempt - 1));
      std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    }
    if (!connected_ && !connect_once(last_why)) {
      last_kind = Kind::connection;
      last_why = "cannot connect: " + last_why;
      continue;
    }
    // TCP: the whole answer, not each byte of it, must come within the timeout.
    const bool bounded = tcp_;
    if (bounded)
      answer_deadline_.arm(
          modbus_get_socket(ctx_),
          std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                 std::chrono::duration<double>(options_.timeout_s)));
    const auto attempt_started = std::chrono::steady_clock::now();
    const int rc = call(ctx_);
    const int err = errno;
    // RTU: a serial line cannot be shut down under a blocked read, so libmodbus waits on (its
    // byte timeout bounds each gap, hence the whole wait by the answer's length), and an
    // answer that came in after the timeout is refused here as late: a trickling instrument
    // is a timeout on either transport.
    if (!tcp_ && rc >= 0 &&
        std::chrono::steady_clock::now() - attempt_started >
            std::chrono::duration<double>(options_.timeout_s)) {
      last_kind = Kind::timeout;
      last_why = fmt::format(
          "no complete answer within {:.0f} ms (it took {:.0f} ms)", options_.timeout_s * 1e3,
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - attempt_started)
              .count());
      modbus_flush(ctx_);
      continue;
    }
    if (bounded && answer_deadline_.disarm()) {
      drop();               // the socket was shut down; the next attempt reconnects
      if (rc >= 0) return;  // the answer completed just as the deadline passed
      last_kind = Kind::timeout;
      last_why = fmt::format("no complete answer within {:.0f} ms", options_.timeout_s * 1e3);
      continue;
    }
    if (rc >= 0) return;
    if (err > MODBUS_ENOBASE && err <= EMBXGTAR) {
      const int code = err - MODBUS_ENOBASE;
      const std::string why = fmt::format("answered Modbus exception {} ({})", code, exception_name(code));
      if (code == MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY || code == MODBUS_EXCEPTION_ACKNOWLEDGE) {
        last_kind = Kind::protocol;
        last_why = why;
        continue;  // the instrument asks us to come back later
      }
      if (code == MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE)
        throw InstrumentFault(instrument_, operation, why + ": the instrument is in a fault state");
      throw ProtocolError(instrument_, operation, why);
    }
    last_why = modbus_strerror(err);
    if (err == ETIMEDOUT) {
      last_kind = Kind::timeout;
      last_why = fmt::format("no complete answer within {:.0f} ms", options_.timeout_s * 1e3);
    } else if (err == EMBBADCRC || err == EMBBADDATA || err == EMBBADEXC || err == EMBUNKEXC ||
               err == EMBMDATA || err == EMBBADSLAVE) {
      last_kind = Kind::protocol;
      last_why = "malformed answer: " + last_why;
    } else {
      last_kind = Kind::connection;
      last_why = "link failed: " + last_why;
    }
    // Resynchronise: a late or partial answer must not be taken for the next one. TCP gets a
    // fresh connection; on a serial line we wait out the rest of the frame and discard it.
    if (tcp_ || last_kind == Kind::connection) {
      drop();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      modbus_flush(ctx_);
    }
  }
  const std::string what =
      options_.retries > 0 ? fmt::format("{} (after {} attempts)", last_why, options_.retries + 1) : last_why;
  switch (last_kind) {
    case Kind::timeout:
      throw TimeoutError(instrument_, operation, what);
    case Kind::protocol:
      throw ProtocolError(instrument_, operation, what);
    case Kind::connection:
      break;
  }
  throw ConnectionError(instrument_, operation, what);
}

// Requests and answers as protocol data units (function code, address, count, data; the
// TCP header / RTU address and CRC are libmodbus's), logged at trace level.
void ModbusLink::read_registers(int function, std::string_view table, int address, int count,
                                std::uint16_t* dest, std::string_view what) {
  if (trace_enabled())
    trace_log().trace("{}: modbus tx {}", instrument_, modbus_pdu_hex(function, address, count));
  // Functions 0x03 and 0x04 differ only in the table they read: one libmodbus call each.
  const auto read =
      function == MODBUS_FC_READ_INPUT_REGISTERS ? modbus_read_input_registers : modbus_read_registers;
  transact(register_operation("read", table, address, count, what), [&](modbus_t* ctx) {
    const int rc = read(ctx, address, count, dest);
    return rc == count || rc < 0 ? rc : (errno = EMBBADDATA, -1);
  });
  if (trace_enabled())
    trace_log().trace("{}: modbus rx {:02x} {:02x} {}", instrument_, function, 2 * count,
                      hex_bytes(register_bytes(dest, count), 512));
}

void ModbusLink::read_input(int address, int count, std::uint16_t* dest, std::string_view what) {
  read_registers(MODBUS_FC_READ_INPUT_REGISTERS, "input", address, count, dest, what);
}

void ModbusLink::read_holding(int address, int count, std::uint16_t* dest, std::string_view what) {
  read_registers(MODBUS_FC_READ_HOLDING_REGISTERS, "holding", address, count, dest, what);
}

void ModbusLink::write_registers(int address, int count, const std::uint16_t* values, std::string_view what) {
  if (trace_enabled())
    trace_log().trace("{}: modbus tx {}", instrument_,
                      modbus_pdu_hex(MODBUS_FC_WRITE_MULTIPLE_REGISTERS, address, count, values, count));
  transact(register_operation("write", "holding", address, count, what),
           [&](modbus_t* ctx) { return modbus_write_registers(ctx, address, count, values); });
  if (trace_enabled())
    trace_log().trace("{}: modbus rx {}", instrument_,
                      modbus_pdu_hex(MODBUS_FC_WRITE_MULTIPLE_REGISTERS, address, count));
}

void ModbusLink::write_register(int address, std::uint16_t value, std::string_view what) {
  if (trace_enabled())
    trace_log().trace("{}: modbus tx {}", instrument_,
                      modbus_pdu_hex(MODBUS_FC_WRITE_SINGLE_REGISTER, address, -1, &value, 1));
  transact(register_operation("write", "holding", address, 1, what),
           [&](modbus_t* ctx) { return modbus_write_register(ctx, address, value); });
  if (trace_enabled())
    trace_log().trace("{}: modbus rx {}", instrument_,
                      modbus_pdu_hex(MODBUS_FC_WRITE_SINGLE_REGISTER, address, -1, &value, 1));
}

}  // namespace tocd::devices
