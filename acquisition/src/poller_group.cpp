#include "poller_group.hpp"

#include <fmt/format.h>

#include "instrument_poller.hpp"
#include "tocd/core/log.hpp"

namespace tocd::acquisition {

namespace {

void guarded(PollerContext& ctx, InstrumentChannel& instrument) {
  const std::string what = instrument.title() + " poller";
  try {
    run_instrument_poller(ctx, instrument);
  } catch (const std::exception& e) {
    logger("acquisition")->error("{} failed: {}", what, e.what());
    ctx.faults.trip(fmt::format("{} failed: {}", what, e.what()));
  } catch (...) {
    logger("acquisition")->error("{} failed", what);
    ctx.faults.trip(fmt::format("{} failed with an unknown error", what));
  }
}

}  // namespace

void PollerGroup::start(const std::vector<InstrumentChannel*>& instruments) {
  for (InstrumentChannel* i : instruments) threads_.emplace_back([this, i] { guarded(ctx_, *i); });
}

void PollerGroup::stop_and_join() {
  stop_.request();
  for (auto& t : threads_) {
    if (t.joinable()) t.join();
  }
  threads_.clear();
}

}  // namespace tocd::acquisition
