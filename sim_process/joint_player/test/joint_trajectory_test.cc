#include <gtest/gtest.h>

#include "sim_process/joint_player/joint_trajectory.h"
#include "components/hand/testing/project_hand.h"

namespace dmpl {
namespace {

using testing::LoadHand;

JointWaypoint Open(double t) {
  return {t, {{"T", {0.3, 0, 0, 0}}, {"F", {0, 0, 0, 0}}, {"M", {0, 0, 0, 0}}, {"R", {0, 0, 0, 0}}}};
}

TEST(JointTrajectoryTest, SmoothstepBetweenWaypointsAndHoldAfter) {
  const HandModel model = LoadHand();
  JointWaypoint closed{1.0, {{"M", {0, 1.0, 1.0, 1.0}}}};  // only M moves; others as before
  const JointTrajectory traj(model, {Open(0.0), closed}, "test");
  const int m1 = model.fingers()[model.FindFinger("M")].joints[1];
  EXPECT_DOUBLE_EQ(traj.At(-1)[m1], 0.0);
  EXPECT_DOUBLE_EQ(traj.At(0.5)[m1], 0.5);
  EXPECT_NEAR(traj.At(0.25)[m1], 0.15625, 1e-12);
  EXPECT_DOUBLE_EQ(traj.At(7.0)[m1], 1.0);
  EXPECT_DOUBLE_EQ(traj.At(0.5)[0], 0.3);
}

TEST(JointTrajectoryTest, BadWaypointsNameTheProblem) {
  const HandModel model = LoadHand();
  auto error = [&](std::vector<JointWaypoint> w) -> std::string {
    try {
      JointTrajectory(model, w, "x.yaml");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error({}).find("empty"), std::string::npos);
  EXPECT_NE(error({Open(1.0), Open(0.5)}).find("times must increase"), std::string::npos);
  EXPECT_NE(error({{0.0, {{"X", {0, 0, 0, 0}}}}}).find("no finger 'X'"), std::string::npos);
  EXPECT_NE(error({{0.0, {{"M", {0, 0}}}}}).find("needs 4 angles"), std::string::npos);
  EXPECT_NE(error({{0.0, {{"M", {0, 0, 0, 0}}}}}).find("has no angle yet"), std::string::npos);
  JointWaypoint bad = Open(0.0);
  bad.q["F"] = {0, 5.0, 0, 0};
  EXPECT_NE(error({bad}).find("outside its limits"), std::string::npos);
}

}  // namespace
}  // namespace dmpl
