// Modbus TCP framing on a byte stream: MBAP header (transaction id, protocol id 0, length of
// unit id + PDU, unit id), then the PDU.
#include "modbus_server/tcp_session.hpp"

#include <chrono>
#include <cstdint>

namespace tocd::mocks {

namespace {

constexpr std::size_t mbap_length = 7;
// The length field counts the unit id and the PDU: at least a function code, at most the
// 253-byte PDU of the Modbus application protocol.
constexpr int min_length_field = 2, max_length_field = 254;

class ModbusTcpSession final : public net::Session {
 public:
  explicit ModbusTcpSession(RegisterServerState state) : s_(state) {}

  bool consume(std::string& input, std::deque<net::Outgoing>& out) override {
    std::size_t at = 0;
    while (input.size() - at >= mbap_length) {
      const auto* p = reinterpret_cast<const std::uint8_t*>(input.data() + at);
      const int protocol = (p[2] << 8) | p[3];
      const int length = (p[4] << 8) | p[5];
      if (protocol != 0 || length < min_length_field || length > max_length_field) return false;
      const std::size_t frame = 6 + static_cast<std::size_t>(length);
      if (input.size() - at < frame) break;
      const ModbusAnswer a = serve_request(true, p, static_cast<int>(frame), s_.map, s_.device,
                                           s_.state_mutex, s_.faults, s_.rng);
      if (a.kind == ModbusAnswer::Kind::close) return false;
      if (a.kind == ModbusAnswer::Kind::send) {
        const auto delay =
            std::chrono::duration_cast<net::Clock::duration>(std::chrono::duration<double>(a.delay_s));
        out.push_back({std::string(a.bytes.begin(), a.bytes.end()), net::Clock::now() + delay});
      }
      at += frame;
    }
    input.erase(0, at);
    return true;
  }

 private:
  RegisterServerState s_;
};

}  // namespace

std::unique_ptr<net::Session> make_modbus_tcp_session(RegisterServerState state) {
  return std::make_unique<ModbusTcpSession>(state);
}

}  // namespace tocd::mocks
