// The physics step's own thread: a job is done when Wait returns, jobs run one after another in
// the order given, what a job throws reaches the caller, and a job under way when it goes is
// finished first.
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "sim_process/sim/background_step.h"

namespace dmpl {
namespace {

TEST(BackgroundStepTest, AJobIsDoneWhenWaitReturnsAndJobsRunInOrder) {
  BackgroundStep step;
  std::vector<int> done;
  for (int i = 0; i < 200; ++i) {
    // Some take longer than the hand-over's spin, some return at once.
    step.Start([&done, i] {
      if (i % 50 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      done.push_back(i);
    });
    EXPECT_TRUE(step.busy() || done.size() == static_cast<size_t>(i + 1));
    step.Wait();
    ASSERT_EQ(done.size(), static_cast<size_t>(i + 1));
    EXPECT_EQ(done.back(), i);
    EXPECT_FALSE(step.busy());
  }
  step.Wait();  // nothing under way: at once
}

TEST(BackgroundStepTest, WhatAJobThrowsIsThrownByWaitOnce) {
  BackgroundStep step;
  step.Start([] { throw std::runtime_error("the physics failed"); });
  EXPECT_THROW(step.Wait(), std::runtime_error);
  step.Wait();
  int ran = 0;
  step.Start([&ran] { ++ran; });
  step.Wait();
  EXPECT_EQ(ran, 1);
}

TEST(BackgroundStepTest, AJobUnderWayWhenItGoesIsFinishedFirst) {
  bool finished = false;
  {
    BackgroundStep step;
    step.Start([&finished] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      finished = true;
    });
  }
  EXPECT_TRUE(finished);
}

}  // namespace
}  // namespace dmpl
