#include <gtest/gtest.h>

#include <cmath>

#include "components/controller/position_planner.h"

namespace dmpl {
namespace {

Eigen::Isometry3d Pose(const Eigen::Vector3d& p, double angle_z) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = p;
  t.linear() = Eigen::AngleAxisd(angle_z, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

TEST(PositionPlannerTest, Equation1IsTheMotionInTheObjectFrame) {
  // O at (1, 0, 0); O' the same place turned 90 deg about z: M is that turn.
  const Eigen::Isometry3d o = Pose({1, 0, 0}, 0.0), o2 = Pose({1, 0, 0}, M_PI / 2);
  const Eigen::Isometry3d m = ObjectMotion(o, o2);
  EXPECT_TRUE(m.translation().isZero(1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(m.linear()).angle(), M_PI / 2, 1e-12);
  EXPECT_TRUE((o * m).isApprox(o2));
}

TEST(PositionPlannerTest, Equation2MovesContactsRigidlyWithTheObject) {
  const Eigen::Isometry3d o = Pose({1, 0, 0}, 0.0), o2 = Pose({1, 0, 0}, M_PI / 2);
  const Eigen::Isometry3d m = ObjectMotion(o, o2);
  // A contact one unit along x from the centre turns to one unit along y.
  EXPECT_TRUE(MoveWithObject(o, m, {2, 0, 0}).isApprox(Eigen::Vector3d(1, 1, 0), 1e-12));
  // Pure translation by (0, 0, 0.01): every contact moves by it.
  const Eigen::Isometry3d up = Pose({1, 0, 0.01}, 0.0);
  EXPECT_TRUE(MoveWithObject(o, ObjectMotion(o, up), {0.3, -0.2, 0.5})
                  .isApprox(Eigen::Vector3d(0.3, -0.2, 0.51), 1e-12));
  // The object's own frame rotated first: O turned 30 deg about z, O' 30 + 45 deg. A contact at
  // distance 0.5 along O's x moves along the arc by 45 deg.
  const Eigen::Isometry3d a = Pose({0, 0, 0}, M_PI / 6), b = Pose({0, 0, 0}, M_PI / 6 + M_PI / 4);
  const Eigen::Vector3d p = a * Eigen::Vector3d(0.5, 0, 0);
  const Eigen::Vector3d expected(0.5 * std::cos(M_PI / 6 + M_PI / 4),
                                 0.5 * std::sin(M_PI / 6 + M_PI / 4), 0);
  EXPECT_TRUE(MoveWithObject(a, ObjectMotion(a, b), p).isApprox(expected, 1e-12));
}

TEST(PositionPlannerTest, StepTowardBoundsBothSpeedsAndArrivesTogether) {
  const Eigen::Isometry3d from = Pose({0, 0, 0}, 0.0), to = Pose({0.1, 0, 0}, 0.2);
  const Eigen::Isometry3d s = StepToward(from, to, 0.01, 0.1);
  // The translation is the tighter limit (0.01 of 0.1 m): a tenth of the way, for the rotation
  // too (0.02 of 0.2 rad), so that both arrive together.
  EXPECT_NEAR(s.translation().x(), 0.01, 1e-12);
  EXPECT_NEAR(AngleBetween(from.linear(), s.linear()), 0.02, 1e-9);
  Eigen::Isometry3d x = from;
  int steps = 0;
  while (!x.isApprox(to, 1e-12) && steps < 100) {
    x = StepToward(x, to, 0.01, 0.1);
    ++steps;
  }
  EXPECT_EQ(steps, 10);
}

}  // namespace
}  // namespace dmpl
