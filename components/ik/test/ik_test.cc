#include <gtest/gtest.h>

#include <random>

#include "components/ik/hand_ik.h"
#include "components/hand/testing/project_hand.h"

namespace dmpl {
namespace {

using testing::LoadHand;

Eigen::VectorXd RandomJoints(const FingerKinematics& f, std::mt19937& rng) {
  Eigen::VectorXd q(f.num_joints());
  for (int k = 0; k < q.size(); ++k) {
    q[k] = std::uniform_real_distribution<double>(f.lower()[k], f.upper()[k])(rng);
  }
  return q;
}

bool WithinLimits(const FingerKinematics& f, const Eigen::VectorXd& q) {
  return ((q - f.lower()).array() >= 0).all() && ((f.upper() - q).array() >= 0).all();
}

TEST(FingerIkTest, ReachesRandomReachableTargetsWithin0_1mm) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  IkParams params;
  params.max_iterations = 200;
  std::mt19937 rng(11);
  int failures = 0, trials = 0;
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const FingerKinematics& finger = kin.finger(f);
    for (int i = 0; i < 250; ++i, ++trials) {
      const Eigen::Vector3d target = finger.TipPosition(RandomJoints(finger, rng));
      const Eigen::VectorXd seed = RandomJoints(finger, rng);
      const IkResult r = SolveFingerIk(finger, seed, target, params);
      EXPECT_TRUE(WithinLimits(finger, r.q));
      if (r.residual_m >= 1e-4) ++failures;
      EXPECT_EQ(r.status == IkStatus::kUnreachable, r.residual_m >= 1e-4);
    }
  }
  EXPECT_EQ(failures, 0) << failures << " of " << trials << " reachable targets missed";
}

TEST(FingerIkTest, UnreachableTargetsGiveBestEffortWithinLimits) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  std::mt19937 rng(5);
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const FingerKinematics& finger = kin.finger(f);
    for (int i = 0; i < 100; ++i) {
      // Far outside the hand's reach.
      const Eigen::Vector3d target =
          Eigen::Vector3d::Random() * 0.3 + Eigen::Vector3d(0.0, 0.0, 0.5);
      const IkResult r = SolveFingerIk(finger, RandomJoints(finger, rng), target, IkParams{});
      EXPECT_TRUE(WithinLimits(finger, r.q));
      EXPECT_EQ(r.status, IkStatus::kUnreachable);
      EXPECT_NEAR(r.residual_m, (target - finger.TipPosition(r.q)).norm(), 1e-12);
    }
  }
}

TEST(FingerIkTest, AnApproachDirectionTurnsTheTipsAxisAtTheSameTipPosition) {
  // The middle finger holds its tip where it is; asked to point its tip 60 deg further round
  // (into an object it touches with the side of its tip), the redundancy turns the distal link
  // toward that direction and the tip stays within the IK's tolerance.
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  const FingerKinematics& finger = kin.finger(kin.FindFinger("M"));
  Eigen::VectorXd q(4);
  q << 0.0, 0.35, 1.2, 1.05;  // a grasp posture (the middle finger over a sphere)
  const Eigen::Vector3d tip = finger.TipPosition(q);
  Eigen::Vector3d axis;
  Eigen::Matrix3Xd omega;
  finger.TipAxis(q, &axis, &omega);
  // Into the object: 60 deg from the tip's axis, in the finger's plane of flexion.
  const Eigen::Vector3d bend = omega.col(1).normalized();
  const Eigen::Vector3d approach = Eigen::AngleAxisd(1.05, bend) * axis;
  IkParams params;
  params.approach_gain = 0.2;
  Eigen::VectorXd now = q;
  for (int tick = 0; tick < 300; ++tick) now = SolveFingerIk(finger, now, tip, params, approach).q;
  Eigen::Vector3d turned;
  finger.TipAxis(now, &turned, &omega);
  EXPECT_LT((finger.TipPosition(now) - tip).norm(), params.tolerance_m);
  EXPECT_LT(std::acos(turned.dot(approach)), std::acos(axis.dot(approach)) - 0.3)
      << "the axis turned from " << std::acos(axis.dot(approach)) << " rad from the approach to "
      << std::acos(turned.dot(approach));
  // Without a gain, or without a direction, the posture is the mid-range pull's alone.
  params.approach_gain = 0.0;
  EXPECT_EQ(SolveFingerIk(finger, q, tip, params, approach).q,
            SolveFingerIk(finger, q, tip, params).q);
}

TEST(HandIkTest, StepIsBoundedNanIsRejectedAndHoldHolds) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  IkParams params;
  HandIk ik(kin, params);
  std::vector<double> q(16, 0.0);
  q[0] = 0.5;  // thumb base inside its limits
  std::vector<std::optional<Eigen::Vector3d>> targets(4);
  const int m = kin.FindFinger("M");
  const Eigen::Vector3d far_target(0.08, 0.0, 0.08);  // a bent middle finger
  targets[m] = far_target;
  std::vector<double> prev = ik.Step(q, targets);
  for (int tick = 0; tick < 400; ++tick) {
    const std::vector<double>& cmd = ik.Step(q, targets);
    for (size_t j = 0; j < cmd.size(); ++j) {
      EXPECT_LE(std::abs(cmd[j] - prev[j]), params.max_joint_step_rad + 1e-12);
    }
    prev = cmd;
  }
  // It got there, in bounded steps.
  EXPECT_LT((kin.TipPosition(m, prev) - far_target).norm(), 1e-4);
  EXPECT_EQ(ik.reports()[m].status, IkStatus::kConverged);
  EXPECT_EQ(ik.reports()[kin.FindFinger("T")].status, IkStatus::kHolding);
  // NaN: rejected, last command held.
  targets[m] = Eigen::Vector3d(std::nan(""), 0.0, 0.0);
  const std::vector<double> held = ik.Step(q, targets);
  EXPECT_EQ(held, prev);
  EXPECT_EQ(ik.reports()[m].status, IkStatus::kRejected);
}

}  // namespace
}  // namespace dmpl
