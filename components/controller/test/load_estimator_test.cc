#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "components/controller/load_estimator.h"

namespace dmpl {
namespace {

TEST(LoadEstimatorTest, ASinkingObjectTeachesTheLoadWhichIsKeptAndBounded) {
  LoadParams p;
  p.enabled = true;
  p.proportional_gain = 40.0;
  p.integral_gain = 800.0;
  p.deadband_m = 0.0005;
  p.reference_follow_s = 0.0;  // a fixed reference
  p.max_load_n = 2.5;
  p.max_net_force_n = 3.0;
  const Eigen::Vector3d gravity(-1, 0, 0);  // palm up
  LoadEstimator load(p);
  const Eigen::Vector3d start(0.07, 0.0, 0.015);
  load.Update(0.001, start, gravity, true);  // the reference
  // 2.5 mm down (2 mm beyond the deadband) and sideways, which teaches nothing: the load is
  // along gravity only.
  const Eigen::Vector3d sunk = start + Eigen::Vector3d(-0.0025, 0.003, -0.001);
  Eigen::Vector3d net;
  for (int k = 0; k < 100; ++k) net = load.Update(0.001, sunk, gravity, true);
  EXPECT_NEAR(load.load_n(), 800.0 * 0.1 * 0.002, 1e-9);  // 0.16 N after 0.1 s
  EXPECT_NEAR(net.x(), 0.16 + 40.0 * 0.002, 1e-9);
  EXPECT_EQ(net.y(), 0.0);
  EXPECT_EQ(net.z(), 0.0);
  // Grasp lost: nothing learned, what was learned is kept.
  EXPECT_NEAR(load.Update(0.001, start - Eigen::Vector3d(0.05, 0, 0), gravity, false).x(), 0.16, 1e-9);
  load.Update(0.001, sunk, gravity, true);  // holding again: a new reference where the object is now
  for (int k = 0; k < 1000; ++k) net = load.Update(0.001, sunk, gravity, true);
  EXPECT_NEAR(load.load_n(), 0.16, 1e-9) << "an object that stays put teaches nothing";
  for (int k = 0; k < 100000; ++k) net = load.Update(0.001, sunk - Eigen::Vector3d(0.01, 0, 0), gravity, true);
  EXPECT_NEAR(load.load_n(), 2.5, 1e-9);
  EXPECT_NEAR(net.x(), 2.5 + 40.0 * 0.0095, 1e-9);
}

TEST(LoadEstimatorTest, TheReferenceFollowsSoOnlySinkingTeaches) {
  LoadParams p;
  p.enabled = true;
  p.proportional_gain = 0.0;
  p.integral_gain = 1000.0;
  p.deadband_m = 0.0;
  p.reference_follow_s = 0.1;
  LoadEstimator load(p);
  const Eigen::Vector3d gravity(-1, 0, 0);  // palm up
  Eigen::Vector3d x(0.07, 0, 0);
  load.Update(0.001, x, gravity, true);
  x.x() -= 0.002;  // a 2 mm step down, then still
  for (int k = 0; k < 2000; ++k) load.Update(0.001, x, gravity, true);
  // The error decays with the follower: the load learned is ki * step * tau (0.2 N).
  EXPECT_NEAR(load.load_n(), 1000.0 * 0.002 * 0.1, 0.01);
  const double learned = load.load_n();
  for (int k = 0; k < 2000; ++k) load.Update(0.001, x, gravity, true);
  EXPECT_NEAR(load.load_n(), learned, 1e-6) << "once it stopped sinking, the load stays";
  // Off: no load at all.
  LoadEstimator off(LoadParams{});
  EXPECT_EQ(off.Update(0.001, x, gravity, true), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace dmpl
