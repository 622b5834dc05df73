// Recovery of the tester driver after each fault the twin injects, and bad answers.
#include "tester_fixture.hpp"
#include "tocd/devices/errors.hpp"

using namespace tocd::devices;
using tocd::mocks::ModbusFault;
using tocd::mocks::ModbusFaultKind;

namespace {
ModbusFault fault(ModbusFaultKind k, int count = 1) {
  ModbusFault f;
  f.kind = k;
  f.count = count;
  return f;
}
}  // namespace

TEST_F(TesterTest, ReconnectsAfterTheTwinDropsTheLink) {
  tester_->read();  // the server has accepted the connection once it answered
  ASSERT_EQ(twin_->connections_accepted(), 1);
  twin_->drop_connections();
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_NO_THROW(tester_->read());
  EXPECT_EQ(twin_->connections_accepted(), 2);
  twin_->inject(fault(ModbusFaultKind::drop_connection));
  EXPECT_NO_THROW(tester_->read());
  EXPECT_EQ(twin_->connections_accepted(), 3);
}

// Each transient fault, once: the retry absorbs it and the read succeeds.
TEST_F(TesterTest, RetriesAbsorbEachTransientFault) {
  for (auto k : {ModbusFaultKind::no_reply, ModbusFaultKind::garbage, ModbusFaultKind::truncated_frame,
                 ModbusFaultKind::short_frame, ModbusFaultKind::drop_connection}) {
    twin_->inject(fault(k));
    EXPECT_NO_THROW(tester_->read()) << static_cast<int>(k);
    EXPECT_EQ(twin_->faults_pending(), 0);
  }
}

// With no retries each fault surfaces as its typed error, and the next call works again.
TEST_F(TesterTest, EachFaultIsATypedErrorWithoutRetries) {
  tester_ = connect_modbus_tcp_tester(twin_->address(), options(0));
  struct Case {
    ModbusFaultKind kind;
    const char* expect;
  };
  for (const Case c :
       {Case{ModbusFaultKind::no_reply, "timeout"}, Case{ModbusFaultKind::truncated_frame, "timeout"},
        Case{ModbusFaultKind::short_frame, "protocol"}, Case{ModbusFaultKind::nan_value, "protocol"},
        Case{ModbusFaultKind::drop_connection, "connection"}}) {
    twin_->inject(fault(c.kind));
    const std::string what = c.expect;
    try {
      tester_->read();
      ADD_FAILURE() << "no error for " << what;
    } catch (const TimeoutError& e) {
      EXPECT_EQ(what, "timeout") << e.what();
    } catch (const ProtocolError& e) {
      EXPECT_EQ(what, "protocol") << e.what();
      EXPECT_NE(std::string(e.what()).find("mechanical tester"), std::string::npos);
    } catch (const ConnectionError& e) {
      EXPECT_EQ(what, "connection") << e.what();
    }
    EXPECT_NO_THROW(tester_->read()) << "after " << what;
  }
  twin_->inject(fault(ModbusFaultKind::garbage));
  EXPECT_THROW(tester_->read(), DeviceError);
  EXPECT_NO_THROW(tester_->read());
}

TEST_F(TesterTest, NanLoadIsAProtocolErrorNamingTheRegister) {
  tester_ = connect_modbus_tcp_tester(twin_->address(), options(0));
  twin_->inject(fault(ModbusFaultKind::nan_value));
  try {
    tester_->read();
    FAIL() << "NaN accepted";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("registers 0..1 (position)"), std::string::npos) << e.what();
  }
}

TEST_F(TesterTest, ExceptionAnswersAreTypedAndNotRetried) {
  ModbusFault f = fault(ModbusFaultKind::exception);
  f.exception_code = 2;
  twin_->inject(f);
  try {
    tester_->read();
    FAIL() << "exception ignored";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("exception 2 (illegal data address)"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("input registers 0..5"), std::string::npos) << e.what();
  }
  f.exception_code = 4;
  twin_->inject(f);
  EXPECT_THROW(tester_->read(), InstrumentFault);
  f.exception_code = 6;  // busy: worth asking again
  twin_->inject(f);
  EXPECT_NO_THROW(tester_->read());
  EXPECT_NO_THROW(tester_->read());
}

TEST_F(TesterTest, DelayedRepliesWithinTheTimeoutAreFineBeyondItTimeOut) {
  ModbusFault f = fault(ModbusFaultKind::delay_reply);
  f.delay_s = 0.05;
  twin_->inject(f);
  EXPECT_NO_THROW(tester_->read());
  tester_ = connect_modbus_tcp_tester(twin_->address(), options(0));
  f.delay_s = 0.4;
  twin_->inject(f);
  const auto t0 = tocd::monotonic_ns();
  EXPECT_THROW(tester_->read(), TimeoutError);
  EXPECT_LT((tocd::monotonic_ns() - t0) * 1e-9, 0.35);
  EXPECT_NO_THROW(tester_->read());
}

TEST_F(TesterTest, PersistentFailureGivesUpAfterTheRetries) {
  twin_->inject(fault(ModbusFaultKind::no_reply, 10));
  const auto t0 = tocd::monotonic_ns();
  try {
    tester_->read();
    FAIL() << "no error";
  } catch (const TimeoutError& e) {
    EXPECT_NE(std::string(e.what()).find("after 3 attempts"), std::string::npos) << e.what();
  }
  EXPECT_LT((tocd::monotonic_ns() - t0) * 1e-9, 3 * 0.2 + 0.5);
  EXPECT_EQ(twin_->faults_pending(), 7);
}

TEST_F(TesterTest, TwinSideLoadLimitTrip) {
  twin_->trip_load_limit();
  const TesterReading r = tester_->read();
  EXPECT_TRUE(r.status.limit);
  EXPECT_EQ(r.status.fault_code, 1);
  tester_->clear_fault();
  EXPECT_FALSE(tester_->read().status.fault);
}
