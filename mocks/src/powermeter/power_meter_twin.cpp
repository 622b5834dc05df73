// The simulated meter's public face: fault counters, message handling shared by both
// transports, stats.
#include <cmath>

#include "powermeter/twin_impl.hpp"
#include "tocd/core/error.hpp"

namespace tocd::mocks {

PowerMeterTwin::Impl::Impl(PowerMeterTwinOptions o)
    : options(o), clock(o.clock ? o.clock : std::make_shared<SimClock>(1.0)), engine(o) {}

PowerMeterTwin::Impl::~Impl() {
  stop_tcp();
}

PowerMeterTwin::Impl::Reply PowerMeterTwin::Impl::handle(std::string_view message) {
  std::lock_guard lock(mutex);
  ++stats.messages;
  Reply r;
  if (drop > 0) {
    --drop;
    r.action = Action::drop;
    return r;
  }
  const auto result = engine.process(message, clock->now_ns());
  if (!result.answer) return r;
  ++stats.queries;
  if (swallow > 0) {
    --swallow;
    return r;
  }
  r.action = Action::answer;
  r.bytes = *result.answer;
  if (garbage > 0) {
    --garbage;
    r.bytes = std::string("\x9C\x01\xFE\x1B[\x80", 6) + r.bytes.substr(0, 3) + std::string("\xFF\x00\x07", 3);
  } else if (non_numeric > 0 && result.numeric) {
    --non_numeric;
    r.bytes = "OVERLOAD";
  }
  auto wait = std::chrono::duration<double>(result.busy_s / clock->factor());
  if (delayed > 0) {
    --delayed;
    wait += delay;
  }
  r.ready = Clock::now() + std::chrono::duration_cast<Clock::duration>(wait);
  return r;
}

PowerMeterTwin::Impl::UsbFault PowerMeterTwin::Impl::take_usb_fault() {
  std::lock_guard lock(mutex);
  if (wrong_tag > 0) return --wrong_tag, UsbFault::wrong_tag;
  if (short_header > 0) return --short_header, UsbFault::short_header;
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
  impl_->delayed = count;
  impl_->delay = delay;
}
void PowerMeterTwin::swallow_replies(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->swallow = count;
}
void PowerMeterTwin::garbage_replies(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->garbage = count;
}
void PowerMeterTwin::non_numeric_replies(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->non_numeric = count;
}
void PowerMeterTwin::over_range_readings(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->engine.force_over_range = count;
}
void PowerMeterTwin::drop_link(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->drop = count;
}
void PowerMeterTwin::push_error(int code, const std::string& message) {
  std::lock_guard lock(impl_->mutex);
  impl_->engine.push_error(code, message);
}
void PowerMeterTwin::usb_wrong_tag(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->wrong_tag = count;
}
void PowerMeterTwin::usb_short_header(int count) {
  std::lock_guard lock(impl_->mutex);
  impl_->short_header = count;
}
void PowerMeterTwin::clear_faults() {
  std::lock_guard lock(impl_->mutex);
  impl_->delayed = impl_->swallow = impl_->garbage = impl_->non_numeric = impl_->drop = 0;
  impl_->wrong_tag = impl_->short_header = 0;
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
