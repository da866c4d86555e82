#include <gtest/gtest.h>

#include "components/runtime/lockstep.h"

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

}  // namespace
}  // namespace dmpl
