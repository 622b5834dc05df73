// Injected faults: each gives a typed error naming the command (or is ridden out by a retry),
// every wait is bounded, and the next operation works again.
#include "pm_fixture.hpp"
#include "tocd/core/clock.hpp"

using namespace pmtest;
using namespace tocd::devices;

namespace {
/// Runs `f`, expects exception E whose message contains every word; returns elapsed seconds.
template <class E, class F>
double expect_error(F&& f, std::initializer_list<const char*> words) {
  const auto t0 = tocd::monotonic_ns();
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const E& e) {
    for (const char* w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
  }
  return static_cast<double>(tocd::monotonic_ns() - t0) * 1e-9;
}
}  // namespace

TEST_P(MeterOverWire, DelayShorterThanTheTimeoutIsWaitedFor) {
  twin->delay_replies(1, std::chrono::milliseconds{100});
  const auto before = meter->client().retried();
  EXPECT_NEAR(meter->measure().power_W, 1e-3, 1e-4);
  EXPECT_EQ(meter->client().retried(), before);
}

TEST_P(MeterOverWire, DelayLongerThanTheTimeoutIsRetriedAndTheLateAnswerDiscarded) {
  light_W = 1e-3;
  twin->delay_replies(1, std::chrono::milliseconds{350});
  EXPECT_NEAR(meter->measure().power_W, 1e-3, 1e-4);
  EXPECT_GE(meter->client().retried(), 1);
  // The late answer must not be taken for the next query's answer.
  EXPECT_EQ(meter->identity().model, "PM100USB");
  EXPECT_EQ(meter->averaging(), 1);
}

TEST_P(MeterOverWire, OneSwallowedAnswerIsRetried) {
  twin->swallow_replies(1);
  EXPECT_EQ(meter->identity().vendor, "Thorlabs");
  EXPECT_GE(meter->client().retried(), 1);
}

TEST_P(MeterOverWire, AMeterThatNeverAnswersTimesOutWithinTheBound) {
  twin->swallow_replies(1000);
  // 3 attempts x (0.2 s + 0.2 s error probe) + backoff: well under 3 s.
  const double s =
      expect_error<TimeoutError>([&] { meter->measure(); }, {"MEAS:POW?", "no answer", "3 attempts"});
  EXPECT_LT(s, 3.0);
  twin->clear_faults();
  EXPECT_GT(meter->measure().power_W, 0.0);
}

TEST_P(MeterOverWire, GarbageBytesAreAProtocolErrorThenTheMeterWorks) {
  twin->garbage_replies(1);
  expect_error<ProtocolError>([&] { meter->measure(); }, {"MEAS:POW?", "not text"});
  EXPECT_NEAR(meter->measure().power_W, 1e-3, 1e-4);
}

TEST_P(MeterOverWire, NonNumericAnswerIsAProtocolErrorQuotingIt) {
  twin->non_numeric_replies(1);
  expect_error<ProtocolError>([&] { meter->measure(); }, {"MEAS:POW?", "expected a number", "\"OVERLOAD\""});
  EXPECT_NEAR(meter->measure().power_W, 1e-3, 1e-4);
}

TEST_P(MeterOverWire, GarbledIdentityIsAProtocolError) {
  twin->non_numeric_replies(0);
  twin->garbage_replies(1);
  EXPECT_THROW(meter->identity(), ProtocolError);
  EXPECT_EQ(meter->identity().vendor, "Thorlabs");
}

TEST_P(MeterOverWire, InjectedOverRangeIsFlagged) {
  twin->over_range_readings(2);
  EXPECT_TRUE(meter->measure().over_range);
  EXPECT_TRUE(meter->read().over_range);
  EXPECT_FALSE(meter->measure().over_range);
}

TEST_P(MeterOverWire, ErrorQueueEntriesAreReportedAfterTheSettingThatRaisedThem) {
  twin->push_error(-300, "Device-specific error");
  twin->push_error(-310, "System error");
  expect_error<InstrumentFault>([&] { meter->set_averaging(3); },
                                {"SENS:AVER:COUN 3", "-300,\"Device-specific error\"", "-310"});
  EXPECT_TRUE(meter->errors().empty());  // drained
  meter->set_averaging(3);
}

TEST_P(MeterOverWire, RefusedQueryIsExplainedByTheErrorQueue) {
  // FETC? with nothing acquired: the meter queues -230 and does not answer.
  meter->configure_power();
  expect_error<InstrumentFault>([&] { meter->fetch(); }, {"FETC?", "-230", "no answer"});
  meter->initiate();
  EXPECT_GT(meter->fetch().power_W, 0.0);
}

TEST_P(MeterOverWire, ReconnectsAfterTheMeterDropsTheLink) {
  twin->drop_link(1);  // the next message closes the connection / unplugs the device
  EXPECT_NEAR(meter->measure().power_W, 1e-3, 1e-4);
  EXPECT_EQ(meter->client().reconnects(), 1);
  // A setting lost with the link is sent again once the link is back.
  twin->drop_link(1);
  meter->set_wavelength_nm(980);
  EXPECT_DOUBLE_EQ(twin->wavelength_nm(), 980.0);
  EXPECT_EQ(meter->client().reconnects(), 2);
}

TEST_P(MeterOverWire, ALinkThatStaysDownIsAConnectionError) {
  if (GetParam() == Wire::tcp)
    twin->stop_tcp();
  else
    twin->set_usb_unplugged(true);
  twin->drop_link(1);
  expect_error<ConnectionError>([&] { meter->measure(); }, {"MEAS:POW?", "attempts"});
  if (GetParam() == Wire::tcp)
    twin->serve_tcp("127.0.0.1", twin->tcp_address().port);
  else
    twin->set_usb_unplugged(false);
  EXPECT_GT(meter->measure().power_W, 0.0);
}

// Instantiated over both wires in test_pm_driver.cpp.
