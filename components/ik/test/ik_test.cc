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
