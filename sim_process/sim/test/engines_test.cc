// The physics both engines share (sim.engine: bullet, mujoco), asserted on each with the same
// parameters: free fall along the palm's gravity, a static grasp that holds, the tactile reading
// of a known contact, the servo's torque limit, determinism, and their configuration errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

#include "components/hand/testing/project_hand.h"
#include "components/runtime/params.h"
#include "sim_process/sim/hand_sim.h"
#include "sim_process/sim/testing/static_grasp.h"

namespace dmpl {
namespace {

using testing::LoadHand;

class EnginesTest : public ::testing::TestWithParam<const char*> {
 protected:
  SimParams Sim(SimParams sim = SimParams{}) const {
    sim.engine = GetParam();
    return sim;
  }
};

// Palm sideways (fingers up): gravity is palm -z; an object far from the hand falls g t^2 / 2.
TEST_P(EnginesTest, AReleasedObjectFallsAlongThePalmsGravity) {
  const HandModel model = LoadHand();
  SimParams sim = Sim();
  sim.palm_rpy = {0.0, 0.0, 0.0};
  ObjectParams object;
  object.position = {0.3, 0.5, 0.5};
  HandSim hand(model, sim, object);
  EXPECT_TRUE(hand.gravity_in_palm().isApprox(Eigen::Vector3d(0, 0, -9.81), 1e-12));
  hand.ReleaseObject();
  const Eigen::Vector3d p0 = hand.object().pose.translation();
  for (int i = 0; i < 300; ++i) hand.Step();
  const double t = 0.3, drop = 0.5 * 9.81 * t * t;
  const Eigen::Vector3d fallen = hand.object().pose.translation() - p0;
  // Bullet and MuJoCo integrate semi-implicitly: the drop over 300 steps is off by ~0.3 %.
  EXPECT_NEAR(-fallen.z(), drop, 0.01 * drop);
  EXPECT_NEAR(fallen.x(), 0.0, 1e-9);
  EXPECT_NEAR(hand.object().linear_velocity.z(), -9.81 * t, 0.01 * 9.81 * t);
}

// The sphere squeezed in the experiments' grasp, released: it stays (drift under 0.1 mm in 3 s,
// the bench's hold criterion; Bullet 0.018, MuJoCo 0.010) on four tips, with a grip of a few
// times its weight.
TEST_P(EnginesTest, AStaticGraspHoldsTheReleasedSphere) {
  const HandModel model = LoadHand();
  ObjectParams object;
  object.position = {0.09, 0.0, 0.02};
  HandSim hand(model, Sim(testing::StaticGraspSim()), object);
  std::string why;
  ASSERT_TRUE(hand.SetJointTargets(testing::SqueezeTargets(), &why)) << why;
  for (int i = 0; i < 300; ++i) hand.Step();
  hand.ReleaseObject();
  for (int i = 0; i < 1000; ++i) hand.Step();
  const Eigen::Vector3d p1 = hand.object().pose.translation();
  for (int i = 0; i < 3000; ++i) hand.Step();
  const Eigen::Vector3d p2 = hand.object().pose.translation();
  double grip = 0.0;
  for (const TipState& t : hand.tactile()) {
    EXPECT_TRUE(t.in_contact);
    grip += t.force;
    // Each reported point lies on the sphere's surface (penetration a fraction of a mm).
    EXPECT_NEAR((t.position - p2).norm(), object.radius, 5e-4);
    EXPECT_GT(t.normal.dot((t.position - p2).normalized()), 0.999);
  }
  const double weight = object.mass * 9.81;
  std::printf("%s: drift %.4f mm in 3 s, grip %.3f N (weight %.3f N)\n", GetParam(),
              (p2 - p1).norm() * 1e3, grip, weight);
  EXPECT_LT((p2 - p1).norm(), 1e-4);
  EXPECT_GT(grip, weight);
  EXPECT_LT(grip, 10 * weight);
}

// Fingers up, a thin box resting on the straight middle finger's tip: the tip reads its weight,
// the normal points down into the tip, the point sits on the tip sphere's top.
TEST_P(EnginesTest, ABoxOnAnUpturnedFingertipWeighsMG) {
  const HandModel model = LoadHand();
  SimParams sim = Sim();
  sim.palm_rpy = {0.0, 0.0, 0.0};
  ObjectParams object;
  object.shape = "box";
  object.size = {0.04, 0.04, 0.01};
  object.position = {0.0, 0.0, 0.1362 + 0.012 + 0.005 + 0.0005};
  HandSim hand(model, sim, object);
  hand.ReleaseObject();
  for (int i = 0; i < 500; ++i) hand.Step();
  const int m = model.FindFinger("M");
  double sum = 0;
  for (int i = 0; i < 500; ++i) {
    hand.Step();
    sum += hand.tactile()[m].force;
    EXPECT_TRUE(hand.tactile()[m].in_contact);
  }
  const double weight = object.mass * 9.81;
  EXPECT_NEAR(sum / 500, weight, 0.05 * weight);
  EXPECT_LT(hand.tactile()[m].normal.z(), -0.99);
  EXPECT_NEAR(hand.tactile()[m].position.z(), 0.1362 + 0.012, 5e-4);
}

// The middle finger's proximal joint driven 0.6 rad into the sphere the other fingers hold: kp
// 2 N*m/rad asks 1.2 N*m of its servo, which gives the URDF's 0.7 N*m and no more; the finger
// presses the sphere (at ~8 cm from the joint, several newtons), on its tip or its links. (As
// the other contacts yield, the finger advances and its servo may leave the limit: MuJoCo's
// softer contacts let it advance 0.1 rad further than Bullet's in 1 s.)
TEST_P(EnginesTest, AServoSaturatesAtTheURDFsEffortLimit) {
  const HandModel model = LoadHand();
  ObjectParams object;
  object.position = {0.09, 0.0, 0.02};
  HandSim hand(model, Sim(testing::StaticGraspSim()), object);
  std::vector<double> q = testing::SqueezeTargets();
  const int m = model.FindFinger("M");
  const int pushed = model.fingers()[m].joints[1];
  q[pushed] += 0.6;
  std::string why;
  ASSERT_TRUE(hand.SetJointTargets(q, &why)) << why;
  double largest_effort = 0.0;
  for (int i = 0; i < 500; ++i) {
    hand.Step();
    const JointState joints = hand.joints();
    for (int a = 0; a < model.num_actuated(); ++a) {
      ASSERT_LE(std::abs(joints.effort[a]), model.actuated_joint(a).effort)
          << model.actuated_joint(a).name << " at step " << i;
    }
    largest_effort = std::max(largest_effort, joints.effort[pushed]);
  }
  EXPECT_EQ(largest_effort, model.actuated_joint(pushed).effort);
  const TipState& tip = hand.tactile()[m];
  std::printf("%s: M presses %.2f N with its tip, %.2f N with its links\n", GetParam(), tip.force,
              tip.link_force);
  EXPECT_GT(tip.force + tip.link_force, 2.0);
}

TEST_P(EnginesTest, TheSameCommandsGiveTheSameRun) {
  const HandModel model = LoadHand();
  ObjectParams object;
  object.position = {0.09, 0.0, 0.02};
  auto run = [&] {
    HandSim hand(model, Sim(testing::StaticGraspSim()), object);
    std::string why;
    hand.SetJointTargets(testing::SqueezeTargets(), &why);
    for (int i = 0; i < 200; ++i) hand.Step();
    hand.ReleaseObject();
    for (int i = 0; i < 300; ++i) hand.Step();
    return std::make_pair(hand.object().pose, hand.joints().position);
  };
  const auto a = run(), b = run();
  EXPECT_EQ(a.first.translation(), b.first.translation());
  EXPECT_TRUE(a.first.linear() == b.first.linear());
  EXPECT_EQ(a.second, b.second);
}

TEST_P(EnginesTest, EveryShapeFallsFree) {
  const HandModel model = LoadHand();
  for (const char* shape : {"sphere", "cylinder", "box", "capsule", "ellipsoid", "prism"}) {
    ObjectParams object;
    object.shape = shape;
    object.position = {0.3, 0.5, 0.5};
    object.rpy = {0.3, 0.2, 0.1};
    HandSim hand(model, Sim(), object);
    EXPECT_TRUE(hand.object().pose.isApprox(
        PoseFromXyzRpy(object.position, object.rpy), 1e-9)) << shape;
    hand.ReleaseObject();
    for (int i = 0; i < 10; ++i) hand.Step();
    EXPECT_LT(hand.object().linear_velocity.x(), -0.05) << shape << " falls";
  }
}

INSTANTIATE_TEST_SUITE_P(BothEngines, EnginesTest, ::testing::Values("bullet", "mujoco"));

// MuJoCo's contact pairs listed once at compile time (sim.mujoco.collision: predefined) give the
// run its broad phase gives, bit for bit: the same contacts, with the same parameters, in the
// same order. Every kind of pair is exercised: the grip eases after the release and the sphere
// slides out past the fingers' links, the box settles on the tips, and fingers swung into each
// other meet (their joints end elsewhere than without self-collision).
struct MujocoRun {
  Eigen::Isometry3d object;
  std::vector<double> joints;
  int tip_touches = 0;   // tip readings in contact, summed over the ticks
  int link_touches = 0;  // ticks a finger's other links pushed on the object
};

MujocoRun RunMujoco(const HandModel& model, const ObjectParams& object, const char* collision,
                    const std::vector<double>& targets, bool self_collision = true) {
  SimParams sim = testing::StaticGraspSim();
  sim.engine = "mujoco";
  sim.mujoco.collision = collision;
  sim.physics.self_collision = self_collision;
  HandSim hand(model, sim, object);  // keeps the model by reference
  std::string why;
  hand.SetJointTargets(testing::SqueezeTargets(), &why);
  for (int i = 0; i < 200; ++i) hand.Step();
  hand.ReleaseObject();
  EXPECT_TRUE(hand.SetJointTargets(targets, &why)) << why;
  MujocoRun run;
  for (int i = 0; i < 400; ++i) {
    hand.Step();
    for (const TipState& t : hand.tactile()) {
      run.tip_touches += t.in_contact;
      run.link_touches += t.link_force > 0;
    }
  }
  run.object = hand.object().pose;
  run.joints = hand.joints().position;
  return run;
}

void ExpectSameRun(const MujocoRun& a, const MujocoRun& b, const std::string& what) {
  EXPECT_EQ(a.object.translation(), b.object.translation()) << what;
  EXPECT_TRUE(a.object.linear() == b.object.linear()) << what;
  EXPECT_EQ(a.joints, b.joints) << what;
  EXPECT_EQ(a.tip_touches, b.tip_touches) << what;
  EXPECT_EQ(a.link_touches, b.link_touches) << what;
}

TEST(MujocoCollisionTest, PredefinedPairsGiveTheBroadPhasesRunBitForBit) {
  const HandModel model = LoadHand();
  ObjectParams object;
  object.position = {0.09, 0.0, 0.02};
  // The grip eased by 3 %: the sphere slides out past the links, the box stays on the tips.
  std::vector<double> eased = testing::SqueezeTargets();
  for (double& q : eased) q *= 0.97;
  const MujocoRun sphere = RunMujoco(model, object, "dynamic", eased);
  EXPECT_GT(sphere.tip_touches, 100);
  EXPECT_GT(sphere.link_touches, 0) << "the sphere passed the links without touching them";
  ExpectSameRun(sphere, RunMujoco(model, object, "predefined", eased), "sphere");
  object.shape = "box";
  const MujocoRun box = RunMujoco(model, object, "dynamic", eased);
  EXPECT_GT(box.tip_touches, 1000) << "4 tips x 400 ticks possible";
  ExpectSameRun(box, RunMujoco(model, object, "predefined", eased), "box");
  // No object within reach; the fore and ring fingers swung into the middle finger (their first
  // joints to 0.45 of their 0.47 rad range, toward it).
  object.position = {0.3, 0.5, 0.5};
  std::vector<double> crossed = testing::SqueezeTargets();
  const std::vector<std::string> joints = model.actuated_names();
  auto index = [&](const std::string& name) {
    return std::find(joints.begin(), joints.end(), name) - joints.begin();
  };
  crossed.at(index("F_j0")) = -0.45;
  crossed.at(index("R_j0")) = 0.45;
  const MujocoRun closed = RunMujoco(model, object, "dynamic", crossed);
  EXPECT_NE(closed.joints, RunMujoco(model, object, "dynamic", crossed, false).joints)
      << "the fingers never met";
  ExpectSameRun(closed, RunMujoco(model, object, "predefined", crossed), "fingers crossed");
}

// The config error a simulator built from these parameters (read from "run.yaml") raises; empty
// if it was built.
std::string ConfigErrorOf(const SimParams& sim, const ObjectParams& object = ObjectParams{}) {
  const HandModel model = LoadHand();
  try {
    HandSim hand(model, sim, object, "run.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(EngineConfigTest, AnUnknownEngineIsAConfigErrorNamingItsKey) {
  SimParams sim;
  sim.engine = "ode";
  const std::string what = ConfigErrorOf(sim);
  ASSERT_FALSE(what.empty()) << "accepted engine 'ode'";
  EXPECT_NE(what.find("run.yaml: key 'sim.engine'"), std::string::npos) << what;
}

// A contact faster than two steps, which MuJoCo would stiffen silently, is refused.
TEST(EngineConfigTest, AContactFasterThanTwoStepsIsAConfigError) {
  SimParams sim;
  sim.engine = "mujoco";
  sim.mujoco.solref = {0.0015, 1.0};
  const std::string what = ConfigErrorOf(sim);
  ASSERT_FALSE(what.empty()) << "accepted a 1.5 ms contact at 1 ms steps";
  EXPECT_NE(what.find("run.yaml: key 'sim.mujoco.solref'"), std::string::npos) << what;
}

// An object too light for MuJoCo's compiler (its inertia below mjMINVAL): one config error that
// names the key and carries MuJoCo's own message.
TEST(EngineConfigTest, AModelMujocoCannotCompileIsAConfigErrorWithItsMessage) {
  SimParams sim;
  sim.engine = "mujoco";
  ObjectParams object;
  object.mass = 1e-20;
  const std::string what = ConfigErrorOf(sim, object);
  ASSERT_FALSE(what.empty()) << "MuJoCo compiled a 1e-20 kg object";
  EXPECT_NE(what.find("run.yaml: key 'sim.engine': MuJoCo could not compile"), std::string::npos)
      << what;
  EXPECT_NE(what.find("mass and inertia"), std::string::npos) << what;
}

TEST(EngineConfigTest, AnUnknownCollisionModeIsAConfigErrorNamingItsKey) {
  SimParams sim;
  sim.engine = "mujoco";
  sim.mujoco.collision = "all";
  const std::string what = ConfigErrorOf(sim);
  EXPECT_NE(what.find("run.yaml: key 'sim.mujoco.collision'"), std::string::npos) << what;
}

}  // namespace
}  // namespace dmpl
