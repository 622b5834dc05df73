#pragma once

#include <memory>
#include <mutex>
#include <random>

#include "modbus_server/register_server.hpp"
#include "net/stream_server.hpp"

namespace tocd::mocks {

/// What a Modbus TCP server answers from; every member outlives the server.
struct RegisterServerState {
  modbus_mapping_t& map;
  RegisterDevice& device;
  std::mutex& state_mutex;
  FaultQueue& faults;
  std::mt19937_64& rng;  ///< used on the server thread only
};

/// One Modbus TCP connection: cuts MBAP frames off the input and serves each. A frame whose
/// header is not Modbus (protocol id other than 0, length outside 2..254) closes the connection,
/// as there is no way to find the next frame in the stream.
std::unique_ptr<net::Session> make_modbus_tcp_session(RegisterServerState state);

}  // namespace tocd::mocks
