// The simulated power meter's SCPI command parser, reached as a host reaches it over USB:
// each input line becomes one program message in a DEV_DEP_MSG_OUT transfer to the meter's
// in-process USBTMC endpoint, and its answer (if any) is fetched with a REQUEST_DEV_DEP_MSG_IN.
// Lines run in order against one meter (fresh for each input), so sequences (zeroing, INIT then FETC?, the
// error queue filling up) are explored too.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "fast_meter.hpp"
#include "fuzz_support.hpp"
#include "tocd/devices/usbtmc.hpp"
#include "tocd/mocks/power_meter_twin.hpp"
#include "tocd/mocks/sim_clock.hpp"

namespace {

namespace usbtmc = tocd::devices::usbtmc;
using tocd::devices::UsbStatus;

tocd::mocks::PowerMeterTwinOptions options() {
  tocd::mocks::PowerMeterTwinOptions o = tocd::fuzz::fast_meter_options();
  o.power_W = [] { return 1e-3; };
  return o;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  tocd::fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tocd::mocks::PowerMeterTwin meter(options());  // fresh per input: a finding replays alone
  const auto endpoint = meter.open_usb_endpoint();
  std::string_view rest = tocd::fuzz::as_text(data, size);
  std::uint8_t tag = 0;
  std::vector<std::uint8_t> in(4096 + usbtmc::header_size + 4);
  while (!rest.empty()) {
    const auto eol = rest.find('\n');
    const std::string_view line = rest.substr(0, eol);
    rest.remove_prefix(eol == std::string_view::npos ? rest.size() : eol + 1);
    tag = usbtmc::next_tag(tag);
    const auto out = usbtmc::encode_dev_dep_msg_out(
        tag, std::span(reinterpret_cast<const std::uint8_t*>(line.data()), line.size()), true);
    const auto sent = endpoint->bulk_out(out, std::chrono::milliseconds(0));
    // The host's own framing is valid, so the meter must take it whatever the message says.
    if (sent.status != UsbStatus::ok) std::abort();
    tag = usbtmc::next_tag(tag);
    const auto request = usbtmc::encode_request_dev_dep_msg_in(tag, 4096);
    if (endpoint->bulk_out(request, std::chrono::milliseconds(0)).status != UsbStatus::ok) std::abort();
    const auto got = endpoint->bulk_in(in, std::chrono::milliseconds(0));
    if (got.status == UsbStatus::ok)
      (void)usbtmc::decode_dev_dep_msg_in(std::span(in.data(), got.length), tag, 4096);  // throws: a finding
  }
  return 0;
}
