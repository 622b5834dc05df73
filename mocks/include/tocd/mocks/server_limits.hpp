#pragma once

#include <chrono>
#include <cstddef>

namespace tocd::mocks {

/// What one simulated-instrument TCP server (tester Modbus TCP, meter SCPI) grants its clients,
/// so that no client, however it behaves, can stall the others or exhaust the process
/// (docs/security.md). The defaults are what `tocdlab simlab` runs with.
struct ServerLimits {
  /// Connections served at once. A newcomer beyond it takes the place of the connection that
  /// has been silent longest (as Modbus/TCP devices do); that connection is closed.
  int max_clients = 256;
  /// Bytes of one unfinished request a client may have sent (an SCPI line without its newline,
  /// a Modbus frame). Beyond it the client is dropped.
  std::size_t max_request_bytes = 64 * 1024;
  /// Answers a client has not read yet. Beyond it the client is dropped instead of anyone
  /// waiting for it.
  std::size_t max_output_bytes = 256 * 1024;
  /// From the first byte of a request to its last: a client that trickles a request slower
  /// than this is dropped.
  std::chrono::milliseconds request_deadline{2000};
  /// Pause before accepting again when accept() fails for lack of file descriptors or memory
  /// (the pending connection would otherwise wake the server at once, for ever).
  std::chrono::milliseconds accept_backoff{100};
};

}  // namespace tocd::mocks
