// USBTMC framing from both ends. The host's decode_dev_dep_msg_in gets the input as one
// DEV_DEP_MSG_IN transfer (as a device might send it); the simulated meter's bulk-OUT check
// gets the input cut into transfers (as a host might send them). The first two bytes choose
// the bTag and the TransferSize the host asked for, and the length of the meter's transfers.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "fast_meter.hpp"
#include "fuzz_support.hpp"
#include "tocd/devices/scpi_link.hpp"
#include "tocd/devices/usbtmc.hpp"
#include "tocd/mocks/power_meter_twin.hpp"

namespace {

namespace usbtmc = tocd::devices::usbtmc;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint8_t tag = data[0];
  const std::uint32_t requested = 1u + data[1] * 17u;
  const std::span<const std::uint8_t> bytes(data + 2, size - 2);

  try {
    const auto header = usbtmc::decode_dev_dep_msg_in(bytes, tag, requested);
    // What the decoder accepts must be what it promises: the payload lies inside the transfer
    // and within what was asked for.
    if (header.transfer_size > requested || usbtmc::header_size + header.transfer_size > bytes.size())
      std::abort();
  } catch (const tocd::devices::LinkError&) {
  }

  tocd::mocks::PowerMeterTwin meter(
      tocd::fuzz::fast_meter_options());  // fresh per input: a finding replays alone
  const auto endpoint = meter.open_usb_endpoint();
  const std::size_t chunk = 12 + 4 * (data[1] % 8);
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    const auto transfer = bytes.subspan(at, std::min(chunk, bytes.size() - at));
    const auto r = endpoint->bulk_out(transfer, std::chrono::milliseconds(0));
    if (r.status == tocd::devices::UsbStatus::stall) endpoint->clear_halt(endpoint->bulk_out_address());
  }
  std::uint8_t in[512];
  (void)endpoint->bulk_in(in, std::chrono::milliseconds(0));
  return 0;
}
