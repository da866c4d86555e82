#include <gtest/gtest.h>

#include "components/runtime/lockstep.h"
#include "components/runtime/resend.h"
#include "dmpl/heartbeat_t.hpp"

namespace dmpl {
namespace {

using Ticks = std::vector<int64_t>;

TEST(LockstepGateTest, FiresOnceWhenAllInputsOfATickArrived) {
  LockstepGate gate({{"state", 0, 0}, {"tactile", 0, 0}});
  EXPECT_EQ(gate.Arrive(0, 0), Ticks{});
  EXPECT_EQ(gate.Missing(), "tactile");
  EXPECT_EQ(gate.Arrive(1, 0), Ticks{0});
  EXPECT_EQ(gate.Arrive(1, 0), Ticks{});  // duplicate: stale
  EXPECT_EQ(gate.stale_count(), 1);
}

TEST(LockstepGateTest, AnswerToPreviousTickIsRequiredFromItsFirstTick) {
  // Controller: sensed state for tick k, and the supervisor's answer to tick k-1 from tick 1 on.
  LockstepGate gate({{"state", 0, 0}, {"task", -1, 1}});
  EXPECT_EQ(gate.Arrive(0, 0), Ticks{0});  // tick 0 does not wait for a task
  EXPECT_EQ(gate.Arrive(0, 1), Ticks{});   // tick 1 waits for task seq 0
  EXPECT_EQ(gate.Missing(), "task");
  EXPECT_EQ(gate.Arrive(1, 0), Ticks{1});
  EXPECT_EQ(gate.Arrive(1, 1), Ticks{});   // task for tick 2 arrives first
  EXPECT_EQ(gate.Arrive(0, 2), Ticks{2});
  EXPECT_EQ(gate.last_tick(), 2);
}

TEST(LockstepGateTest, TheDrivingInputMayRunAheadAndTicksStillFireInOrder) {
  // An actuation delay lets the simulator publish tick k + 1 before tick k has its task.
  LockstepGate gate({{"state", 0, 0}, {"task", -1, 1}});
  EXPECT_EQ(gate.Arrive(0, 0), Ticks{0});
  EXPECT_EQ(gate.Arrive(0, 1), Ticks{});
  EXPECT_EQ(gate.Arrive(0, 2), Ticks{});
  EXPECT_EQ(gate.Arrive(1, 0), Ticks{1});  // serves tick 1 only: tick 2 waits for task 1
  EXPECT_EQ(gate.Missing(), "task");
  EXPECT_EQ(gate.Arrive(1, 1), Ticks{2});
  EXPECT_EQ(gate.Missing(), "state, task");
}

TEST(LockstepGateTest, AnAnswerEveryTenthTickServesTheTenTicksAfterIt) {
  // The supervisor answers ticks 0, 10, 20...: its answer to tick 10 serves ticks 11..20.
  LockstepGate gate({{"state", 0, 0}, {"task", -1, 1, 10}});
  EXPECT_EQ(gate.Arrive(0, 0), Ticks{0});
  EXPECT_EQ(gate.Arrive(0, 1), Ticks{});
  EXPECT_EQ(gate.Arrive(0, 2), Ticks{});
  EXPECT_EQ(gate.Arrive(1, 0), (Ticks{1, 2}));
  for (int64_t k = 3; k <= 10; ++k) EXPECT_EQ(gate.Arrive(0, k), Ticks{k});
  EXPECT_EQ(gate.Arrive(0, 11), Ticks{});  // needs the answer to tick 10
  EXPECT_EQ(gate.Arrive(1, 10), Ticks{11});
  for (int64_t k = 12; k <= 20; ++k) EXPECT_EQ(gate.Arrive(0, k), Ticks{k});
  EXPECT_EQ(gate.Arrive(0, 21), Ticks{});  // needs the answer to tick 20
  EXPECT_EQ(gate.Missing(), "task");
  EXPECT_EQ(gate.Arrive(1, 0), Ticks{});   // an old answer is stale
  EXPECT_EQ(gate.stale_count(), 1);
}

TEST(LockstepGateTest, OldMessagesAreStale) {
  LockstepGate gate({{"cmd", 0, 0}});
  EXPECT_EQ(gate.Arrive(0, 5), Ticks{5});  // a node started late picks up where the loop is
  EXPECT_EQ(gate.Arrive(0, 3), Ticks{});
  EXPECT_EQ(gate.stale_count(), 1);
  EXPECT_EQ(gate.Arrive(0, 6), Ticks{6});
}

TEST(LockstepGateTest, ConsecutiveTicksWaitForALostOneToBeSentAgain) {
  LockstepGate gate({{"state", 0, 0}}, /*consecutive=*/true);
  EXPECT_EQ(gate.Arrive(0, 0), Ticks{0});
  EXPECT_EQ(gate.Arrive(0, 2), Ticks{});  // tick 1 was lost: tick 2 waits
  EXPECT_EQ(gate.Missing(), "state");
  EXPECT_EQ(gate.Arrive(0, 3), Ticks{});
  EXPECT_EQ(gate.Arrive(0, 1), (Ticks{1, 2, 3}));  // sent again
  EXPECT_EQ(gate.Arrive(0, 2), Ticks{});           // a copy
  EXPECT_EQ(gate.stale_count(), 1);
}

TEST(InOrderTest, DeliversEachSeqOnceInOrderFromTheFirstSeen) {
  InOrder<int> stream(/*max_ahead=*/100);
  std::vector<int> ready;
  EXPECT_EQ(stream.Arrive(7, 70, &ready), InOrder<int>::Verdict::kAccepted);
  EXPECT_EQ(ready, std::vector<int>{70});
  stream.Arrive(9, 90, &ready);
  EXPECT_TRUE(ready.empty());  // 8 was lost
  EXPECT_EQ(stream.waiting(), 1u);
  stream.Arrive(9, 91, &ready);  // a copy of a waiting one changes nothing
  stream.Arrive(8, 80, &ready);
  EXPECT_EQ(ready, (std::vector<int>{80, 90}));
  EXPECT_EQ(stream.Arrive(8, 80, &ready), InOrder<int>::Verdict::kDuplicate);
  EXPECT_TRUE(ready.empty());
  // A forged seq far ahead is refused, and the stream goes on.
  EXPECT_EQ(stream.Arrive(1000000000, 0, &ready), InOrder<int>::Verdict::kTooFarAhead);
  stream.Arrive(10, 100, &ready);
  EXPECT_EQ(ready, std::vector<int>{100});
}

TEST(ResenderTest, SendsItsLastMessagesAgainWhileStalledBackingOff) {
  lcm::LCM lcm("memq://");
  ASSERT_TRUE(lcm.good());
  std::vector<int64_t> seen;
  struct Counter {
    std::vector<int64_t>* seen;
    void On(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* m) {
      seen->push_back(m->seq);
    }
  } counter{&seen};
  lcm.subscribe("X", &Counter::On, &counter);
  Resender resender(/*depth=*/2, /*stall_s=*/0.01);
  heartbeat_t m{};
  for (int64_t k = 0; k < 3; ++k) {
    m.seq = k;
    resender.Publish(lcm, "X", m, /*now=*/0.0);
  }
  EXPECT_EQ(resender.Poll(0.005), 0);  // not stalled yet
  EXPECT_EQ(resender.Poll(0.010), 2);  // the last two, oldest first
  EXPECT_EQ(resender.Poll(0.025), 0);  // then after 2x as long
  EXPECT_EQ(resender.Poll(0.030), 2);
  m.seq = 3;
  resender.Publish(lcm, "X", m, 0.031);  // progress: the wait starts again
  EXPECT_EQ(resender.Poll(0.035), 0);
  EXPECT_EQ(resender.resent(), 4);
  while (lcm.handleTimeout(0) > 0) {
  }
  EXPECT_EQ(seen, (std::vector<int64_t>{0, 1, 2, 1, 2, 1, 2, 3}));
  Resender off(2, 0.0);  // real time: nothing is kept
  off.Publish(lcm, "X", m, 0.0);
  EXPECT_EQ(off.Poll(10.0), 0);
}

}  // namespace
}  // namespace dmpl
