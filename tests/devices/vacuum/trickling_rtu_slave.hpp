#pragma once

// A Modbus RTU slave on a pseudo-terminal that answers every "read input registers" request
// correctly (all registers zero) but one byte at a time, with a pause after each byte: a
// controller (or a USB-serial adapter) that trickles its answer, each gap inside libmodbus's
// byte timeout, so that only a bound on the whole answer catches it.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <unistd.h>

namespace tocd::devices::testing {

class TricklingRtuSlave {
 public:
  TricklingRtuSlave(int slave_id, std::chrono::milliseconds gap) : slave_id_(slave_id), gap_(gap) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0)
      throw std::runtime_error("cannot open a pseudo-terminal");
    device_ = ::ptsname(master_);
    thread_ = std::thread([this] { serve(); });
  }
  ~TricklingRtuSlave() {
    stop_ = true;
    thread_.join();
    ::close(master_);
  }
  TricklingRtuSlave(const TricklingRtuSlave&) = delete;
  TricklingRtuSlave& operator=(const TricklingRtuSlave&) = delete;

  const std::string& device() const { return device_; }

 private:
  static std::uint16_t crc16(const std::uint8_t* p, std::size_t n) {
    std::uint16_t crc = 0xFFFF;
    for (std::size_t i = 0; i < n; ++i) {
      crc ^= p[i];
      for (int b = 0; b < 8; ++b)
        crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
    }
    return crc;
  }

  void serve() {
    std::vector<std::uint8_t> request;
    while (!stop_) {
      pollfd p{master_, POLLIN, 0};
      if (::poll(&p, 1, 20) <= 0) continue;
      std::uint8_t buf[64];
      const ssize_t n = ::read(master_, buf, sizeof buf);
      if (n <= 0) continue;
      request.insert(request.end(), buf, buf + n);
      if (request.size() < 8) continue;  // a read request is 8 bytes
      if (request[0] == slave_id_ && request[1] == 0x04) answer(request[5]);
      request.clear();
    }
  }

  void answer(int registers) {
    std::vector<std::uint8_t> a{static_cast<std::uint8_t>(slave_id_), 0x04,
                                static_cast<std::uint8_t>(2 * registers)};
    a.resize(a.size() + 2 * static_cast<std::size_t>(registers), 0);
    const std::uint16_t crc = crc16(a.data(), a.size());
    a.push_back(static_cast<std::uint8_t>(crc & 0xFF));
    a.push_back(static_cast<std::uint8_t>(crc >> 8));
    for (const std::uint8_t byte : a) {
      if (stop_ || ::write(master_, &byte, 1) != 1) return;
      std::this_thread::sleep_for(gap_);
    }
  }

  int slave_id_;
  std::chrono::milliseconds gap_;
  int master_ = -1;
  std::string device_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace tocd::devices::testing
