#include "supervisor/blackboard.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dmpl {
namespace {

// One fingertip (1.2 cm radius) touching a 2.5 cm sphere centred at `centre` from direction
// `from` (unit), its axis `axis`.
FingerView Touching(const Eigen::Vector3d& centre, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& axis, double force = 1.0) {
  FingerView f;
  f.in_contact = true;
  f.force = force;
  f.contact = centre + 0.025 * from;
  f.tip = centre + 0.037 * from;
  f.tip_axis = axis;
  return f;
}

TEST(BlackboardTest, TheSurfaceIsLearnedInTheObjectsFrameWithTheTipsRadius) {
  Blackboard board({"T", "F"});
  board.view.fingers.resize(2);
  board.view.object.translation() = Eigen::Vector3d(0.07, 0.0, 0.015);
  board.view.object.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).matrix();
  const Eigen::Vector3d centre = board.view.object.translation();
  // Contacts all round the sphere, a few at a time.
  for (int i = 0; i < 60; ++i) {
    const double a = 0.37 * i, b = 0.23 * i;
    const Eigen::Vector3d d(std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b));
    board.view.fingers[0] = Touching(centre, d, -d);
    board.view.fingers[1] = Touching(centre, -d, d, 0.01);  // too light to count
    board.now = 0.01 * i;
    board.LearnSurface();
  }
  EXPECT_NEAR(board.tip_radius_m, 0.012, 1e-9);
  EXPECT_GT(board.surface.size(), 20u);
  // The surface is 2.5 cm from the centre wherever it was felt, in the object's frame.
  const SurfacePoint s = board.surface.Along(Eigen::Vector3d(1, 1, 0.2));
  ASSERT_TRUE(s.known);
  EXPECT_NEAR(s.distance_m, 0.025, 5e-4);
  EXPECT_GT(s.normal.dot(Eigen::Vector3d(1, 1, 0.2).normalized()), 0.99);
}

TEST(BlackboardTest, AContactsAngleRunsFromTheTipsAxisToTheNormalIntoTheObject) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.0), y = Eigen::Vector3d::UnitY();
  // Touching with its front (its axis into the object): 0; with its side: 90 deg.
  EXPECT_NEAR(Touching(centre, y, -y).ContactAngle(), 0.0, 1e-9);
  EXPECT_NEAR(Touching(centre, y, -Eigen::Vector3d::UnitZ()).ContactAngle(), M_PI / 2, 1e-9);
  // Round past the side toward its link.
  const Eigen::Vector3d back = Eigen::Vector3d(0, 0.3, 1).normalized();
  EXPECT_NEAR(Touching(centre, y, back).ContactAngle(),
              M_PI / 2 + std::asin(0.3 / std::hypot(0.3, 1.0)), 1e-9);
  FingerView free = Touching(centre, y, -y);
  free.in_contact = false;
  EXPECT_EQ(free.ContactAngle(), 0.0);
  // Still in contact for the controller's debounce, the point already gone (zeros, 0 N).
  FingerView losing = Touching(centre, y, back);
  losing.contact.setZero();
  losing.force = 0.0;
  EXPECT_FALSE(losing.SensesPoint());
  EXPECT_EQ(losing.ContactAngle(), 0.0);
}

}  // namespace
}  // namespace dmpl
