#include <gtest/gtest.h>

#include <random>

#include "components/kinematics/hand_kinematics.h"
#include "components/hand/testing/project_hand.h"
#include "components/kinematics/urdf_to_kdl.h"
#include "sim_process/sim/hand_sim.h"

namespace dmpl {
namespace {

using testing::LoadHand;

// Every actuated joint drawn uniformly within its limits.
std::vector<double> RandomHandJoints(const HandModel& model, std::mt19937* rng) {
  std::vector<double> q(model.num_actuated());
  for (int a = 0; a < model.num_actuated(); ++a) {
    const JointInfo& j = model.actuated_joint(a);
    q[a] = std::uniform_real_distribution<double>(j.lower, j.upper)(*rng);
  }
  return q;
}

// A finger's joints drawn uniformly within its limits.
Eigen::VectorXd RandomFingerJoints(const FingerKinematics& finger, std::mt19937* rng) {
  Eigen::VectorXd q(finger.num_joints());
  for (int k = 0; k < q.size(); ++k) {
    q[k] = std::uniform_real_distribution<double>(finger.lower()[k], finger.upper()[k])(*rng);
  }
  return q;
}

TEST(UrdfToKdlTest, TreeHasEverySegmentAndTheActuatedJoints) {
  const HandModel model = LoadHand();
  const KDL::Tree tree = UrdfToKdlTree(model);
  EXPECT_EQ(tree.getNrOfSegments(), model.links().size() - 1);
  EXPECT_EQ(tree.getNrOfJoints(), 16u);
}

TEST(HandKinematicsTest, ForwardKinematicsAgreesWithTheSimulatorWithin0_1mm) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  ObjectParams object;
  object.position = {0.5, 0.5, 0.5};  // out of the way
  HandSim sim(model, SimParams{}, object);
  std::mt19937 rng(7);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<double> q = RandomHandJoints(model, &rng);
    sim.SetJointPositions(q);
    for (int f = 0; f < kin.num_fingers(); ++f) {
      worst = std::max(worst, (kin.TipPosition(f, q) - sim.TipPosition(f)).norm());
    }
  }
  EXPECT_LT(worst, 1e-4);
}

TEST(HandKinematicsTest, JacobianMatchesFiniteDifferences) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  std::mt19937 rng(3);
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const FingerKinematics& finger = kin.finger(f);
    const Eigen::VectorXd q = RandomFingerJoints(finger, &rng);
    const Eigen::Vector3d tip = finger.TipPosition(q);
    Eigen::Matrix3Xd jac;
    finger.PositionJacobian(q, &jac);
    for (int k = 0; k < q.size(); ++k) {
      Eigen::VectorXd dq = q;
      dq[k] += 1e-7;
      const Eigen::Vector3d numeric = (finger.TipPosition(dq) - tip) / 1e-7;
      EXPECT_LT((numeric - jac.col(k)).norm(), 1e-5) << finger.name() << " joint " << k;
    }
  }
}

TEST(HandKinematicsTest, PointJacobianMatchesFiniteDifferencesOfAPointOnTheTip) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  std::mt19937 rng(5);
  const Eigen::Vector3d offset(0.004, -0.006, 0.003);  // about a tip radius off its centre
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const FingerKinematics& finger = kin.finger(f);
    const Eigen::VectorXd q = RandomFingerJoints(finger, &rng);
    std::vector<Eigen::Isometry3d> frames;
    finger.LinkFrames(q, &frames);
    // The point in the tip's own frame: it moves with the tip.
    const Eigen::Vector3d local = frames.back().inverse() * (finger.TipPosition(q) + offset);
    Eigen::Matrix3Xd jac;
    finger.PointJacobian(q, offset, &jac);
    for (int k = 0; k < q.size(); ++k) {
      Eigen::VectorXd dq = q;
      dq[k] += 1e-7;
      finger.LinkFrames(dq, &frames);
      const Eigen::Vector3d numeric =
          (frames.back() * local - (finger.TipPosition(q) + offset)) / 1e-7;
      EXPECT_LT((numeric - jac.col(k)).norm(), 1e-5) << finger.name() << " joint " << k;
    }
  }
}

// The servos' gravity compensation (the simulator's, from Bullet's links) is what the URDF's
// masses give: a finger held still at its target, its effort is the gravity torque alone.
TEST(HandKinematicsTest, GravityTorquesAreTheSimulatorsCompensation) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  ObjectParams object;
  object.position = {0.5, 0.5, 0.5};  // out of the way
  SimParams params;
  params.physics.gravity = {3.0, -5.0, -7.5};  // not along a palm axis
  HandSim sim(model, params, object);
  std::mt19937 rng(11);
  double largest = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<double> q = RandomHandJoints(model, &rng);
    sim.SetJointPositions(q);
    std::string why;
    ASSERT_TRUE(sim.SetJointTargets(q, &why)) << why;
    sim.Step();  // the servos' torque at q, at rest on its target: the compensation alone
    const std::vector<double> effort = sim.joints().effort;
    for (int f = 0; f < kin.num_fingers(); ++f) {
      const Eigen::VectorXd tau =
          kin.finger(f).GravityTorques(kin.FingerJoints(f, q), sim.gravity_in_palm());
      for (int k = 0; k < tau.size(); ++k) {
        const double sensed = effort[kin.joint_indices(f)[k]];
        largest = std::max(largest, std::abs(sensed));
        EXPECT_NEAR(tau[k], sensed, 1e-4) << kin.finger(f).name() << " joint " << k;
      }
    }
  }
  EXPECT_GT(largest, 5e-3) << "a test that cannot fail";
}

}  // namespace
}  // namespace dmpl
