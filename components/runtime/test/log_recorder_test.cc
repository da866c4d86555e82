// The recorder keeps one copy of a message sent again after a loss, and none of another run's.
#include "components/runtime/log_recorder.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <string>

#include "components/runtime/channels.h"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/sim_control_t.hpp"
#include "dmpl/sim_status_t.hpp"

namespace dmpl {
namespace {

class LogRecorderTest : public ::testing::Test {
 protected:
  LogRecorderTest() : bus_("memq://", false) {}
  ~LogRecorderTest() override { std::remove(path_.c_str()); }

  template <typename Msg>
  void Publish(const std::string& channel, const Msg& m) {
    bus_.Publish(channel, m);
  }
  void Drain() {
    while (bus_.in_process()->DeliverOne()) {
    }
  }
  static hand_sensors_t Truth(int64_t run_id, int64_t seq) {
    hand_sensors_t m{};
    m.run_id = run_id;
    m.seq = seq;
    return m;
  }

  LcmBus bus_;
  // One file per test: ctest runs the tests of this file in parallel processes.
  std::string path_ = ::testing::TempDir() + "dmpl_log_recorder_test_" +
                      ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                      std::to_string(getpid()) + ".lcmlog";
};

TEST_F(LogRecorderTest, KeepsOneCopyOfAMessageSentAgain) {
  RecordOptions options;
  options.log_path = path_;
  LogRecorder recorder(&bus_, options);
  Publish(channels::kSensorsTrue, Truth(0, 1));
  Publish(channels::kSensorsTrue, Truth(0, 2));
  Publish(channels::kSensorsTrue, Truth(0, 1));  // sent again: the same bytes
  Drain();
  EXPECT_EQ(recorder.written(), 2);
  EXPECT_EQ(recorder.copies(), 1);
}

TEST_F(LogRecorderTest, RecordsNothingOfAnotherRun) {
  RecordOptions options;
  options.log_path = path_;
  options.run_id = 7;
  LogRecorder recorder(&bus_, options);
  Publish(channels::kSensorsTrue, Truth(7, 1));  // this run's
  Publish(channels::kSensorsTrue, Truth(5, 1));  // another run's
  Publish(channels::kSensorsTrue, Truth(0, 2));  // none, on a loop channel: not this run's
  sim_control_t pause{};                         // none, on a control channel: sent by hand, kept
  pause.seq = 2;
  Publish(channels::kSimControl, pause);
  sim_status_t status{};                         // a type without a run: kept
  status.seq = 3;
  Publish(channels::kSimStatus, status);
  Drain();
  EXPECT_EQ(recorder.written(), 3);
  EXPECT_EQ(recorder.foreign(), 2);
}

}  // namespace
}  // namespace dmpl
