#pragma once

#include <cstdint>

namespace tocd::mocks {

/// A misbehaviour a Modbus twin shows on its next `count` requests (then it behaves again).
enum class ModbusFaultKind {
  delay_reply,      ///< answer correctly after `delay_s` (simulated clock not involved: real seconds)
  no_reply,         ///< swallow the request: the client times out
  exception,        ///< answer with Modbus exception `exception_code`
  drop_connection,  ///< close the TCP connection instead of answering (TCP twins)
  garbage,          ///< answer with random bytes
  bad_crc,          ///< answer correctly but with a corrupted CRC (RTU twins)
  wrong_slave,      ///< answer as another slave id
  short_frame,      ///< a well-formed answer carrying fewer registers than asked for
  truncated_frame,  ///< the first bytes of a correct answer, then silence
  nan_value,        ///< the first float of a read answer is NaN
};

struct ModbusFault {
  ModbusFaultKind kind = ModbusFaultKind::no_reply;
  int count = 1;
  double delay_s = 0.0;
  std::uint8_t exception_code = 4;  ///< 4 = slave device failure
};

}  // namespace tocd::mocks
