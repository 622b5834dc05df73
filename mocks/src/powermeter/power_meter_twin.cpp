// The simulated meter's public face: fault counters, message handling shared by both
// transports, stats.
#include <cmath>

#include "powermeter/twin_impl.hpp"
#include "tocd/core/error.hpp"

namespace tocd::mocks {
namespace {

/// Whether a fault counter applies to this message; counts it down when it does.
bool take(int& counter) {
  if (counter <= 0) return false;
  --counter;
  return true;
}

}  // namespace

PowerMeterTwin::Impl::Impl(PowerMeterTwinOptions o)
    : options(o), clock(o.clock ? o.clock : std::make_shared<SimClock>(1.0)), engine(o) {}

PowerMeterTwin::Impl::~Impl() {
  stop_tcp();
}

PowerMeterTwin::Impl::Reply PowerMeterTwin::Impl::handle(std::string_view message) {
  std::lock_guard lock(mutex);
  ++stats.messages;
  Reply r;
  if (take(faults.drop)) {
    r.action = Action::drop;
    return r;
  }
  const auto result = engine.process(message, clock->now_ns());
  if (!result.answer) return r;
  ++stats.queries;
  if (take(faults.swallow)) return r;
  r.action = Action::answer;
  r.bytes = *result.answer;
  if (take(faults.garbage)) {
    r.bytes = std::string("\x9C\x01\xFE\x1B[\x80", 6) + r.bytes.substr(0, 3) + std::string("\xFF\x00\x07", 3);
  } else if (result.numeric && take(faults.non_numeric)) {
    r.bytes = "OVERLOAD";
  }
  auto wait = std::chrono::duration<double>(result.busy_s / clock->factor());
  if (take(faults.delayed)) wait += faults.delay;
  r.ready = Clock::now() + std::chrono::duration_cast<Clock::duration>(wait);
  return r;
}

PowerMeterTwin::Impl::UsbFault PowerMeterTwin::Impl::take_usb_fault() {
  std::lock_guard lock(mutex);
  if (take(faults.wrong_tag)) return UsbFault::wrong_tag;
  if (take(faults.short_header)) return UsbFault::short_header;
  return UsbFault::none;
}

void PowerMeterTwin::Impl::note_usb_rejection(const std::string& why) {
  std::lock_guard lock(mutex);
  ++stats.usb_rejected;
  stats.last_usb_rejection = why;
}

PowerMeterTwin::PowerMeterTwin(PowerMeterTwinOptions options) {
  if (!(options.max_power_W > 0.0) || options.noise_relative < 0.0 || options.noise_floor_W < 0.0 ||
      !(options.sample_time_s >= 0.0) || !(options.zero_duration_s >= 0.0))
    throw ConfigError("simulated power meter: max power must be positive; noise, sample and zero times >= 0");
  impl_ = std::make_shared<Impl>(std::move(options));
}

PowerMeterTwin::~PowerMeterTwin() {
  impl_->stop_tcp();
}

int PowerMeterTwin::serve_tcp(const std::string& host, int port) {
  return impl_->start_tcp(host, port);
}
void PowerMeterTwin::stop_tcp() {
  impl_->stop_tcp();
}

devices::ScpiTcpAddress PowerMeterTwin::tcp_address() const {
  std::lock_guard lock(impl_->mutex);
  return {impl_->tcp_host, impl_->tcp_port};
}

void PowerMeterTwin::set_usb_unplugged(bool unplugged) {
  std::lock_guard lock(impl_->mutex);
  impl_->usb_unplugged = unplugged;
}

void PowerMeterTwin::delay_replies(int count, std::chrono::milliseconds delay) {
  std::lock_guard lock(impl_->mutex);
  impl_->faults.delayed = count;
  impl_->faults.delay = delay;
}
void PowerMeterTwin::swallow_replies(int count) {
  impl_->arm(&Impl::Faults::swallow, count);
}
void PowerMeterTwin::garbage_replies(int count) {
  impl_->arm(&Impl::Faults::garbage, count);
}
void PowerMeterTwin::non_numeric_replies(int count) {
  impl_->arm(&Impl::Faults::non_numeric, count);
}
void PowerMeterTwin::over_range_readings(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->engine.force_over_range = count;
}
void PowerMeterTwin::drop_link(int count) {
  impl_->arm(&Impl::Faults::drop, count);
}
void PowerMeterTwin::push_error(int code, const std::string& message) {
  std::lock_guard lock(impl_->mutex);
  impl_->engine.push_error(code, message);
}
void PowerMeterTwin::usb_wrong_tag(int count) {
  impl_->arm(&Impl::Faults::wrong_tag, count);
}
void PowerMeterTwin::usb_short_header(int count) {
  impl_->arm(&Impl::Faults::short_header, count);
}
void PowerMeterTwin::clear_faults() {
  std::lock_guard lock(impl_->mutex);
  impl_->faults = {};  // every counter, so a new one cannot be missed here
  impl_->engine.force_over_range = 0;
}

double PowerMeterTwin::wavelength_nm() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->engine.wavelength_nm();
}
int PowerMeterTwin::averaging() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->engine.averaging();
}
bool PowerMeterTwin::auto_range() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->engine.auto_range();
}
PowerMeterTwinStats PowerMeterTwin::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace tocd::mocks
