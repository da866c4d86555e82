#include <gtest/gtest.h>

#include "components/runtime/lockstep.h"

namespace dmpl {
namespace {

TEST(LockstepGateTest, FiresOnceWhenAllInputsOfATickArrived) {
  LockstepGate gate({{"state", 0, 0}, {"tactile", 0, 0}});
  EXPECT_FALSE(gate.Arrive(0, 0));
  EXPECT_EQ(gate.Missing(), "tactile");
  auto t = gate.Arrive(1, 0);
  ASSERT_TRUE(t);
  EXPECT_EQ(*t, 0);
  EXPECT_FALSE(gate.Arrive(1, 0));  // duplicate: stale
  EXPECT_EQ(gate.stale_count(), 1);
}

TEST(LockstepGateTest, AnswerToPreviousTickIsRequiredFromItsFirstTick) {
  // Controller: sensed state for tick k, and the supervisor's answer to tick k-1 from tick 1 on.
  LockstepGate gate({{"state", 0, 0}, {"task", -1, 1}});
  ASSERT_TRUE(gate.Arrive(0, 0));           // tick 0 does not wait for a task
  EXPECT_FALSE(gate.Arrive(0, 1));          // tick 1 waits for task seq 0
  EXPECT_EQ(gate.Missing(), "task");
  auto t = gate.Arrive(1, 0);
  ASSERT_TRUE(t);
  EXPECT_EQ(*t, 1);
  ASSERT_TRUE(gate.Arrive(1, 1) == std::nullopt);  // task for tick 2 arrives first
  ASSERT_TRUE(gate.Arrive(0, 2));
  EXPECT_EQ(gate.last_tick(), 2);
}

TEST(LockstepGateTest, OldMessagesAreStale) {
  LockstepGate gate({{"cmd", 0, 0}});
  ASSERT_TRUE(gate.Arrive(0, 5));
  EXPECT_FALSE(gate.Arrive(0, 3));
  EXPECT_EQ(gate.stale_count(), 1);
  EXPECT_TRUE(gate.Arrive(0, 6));
}

}  // namespace
}  // namespace dmpl
