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

// Finger 0 slides 1.5 cm in 1.5 s with role `role` over the 5 cm cube's -y face, or round a 2.5
// cm sphere's equator; returns the faces felt flat.
std::vector<FlatFace> FlatFacesAfterASlide(Role role, bool sphere) {
  Blackboard board({"R"});
  board.view.fingers.resize(1);
  board.out.task.fingers.resize(1);
  board.out.task.fingers[0].role = role;
  board.view.object.translation() = Eigen::Vector3d(0.07, 0.0, 0.015);
  const Eigen::Vector3d centre = board.view.object.translation();
  for (int i = 0; i <= 150; ++i) {
    const double along = 0.0001 * i;  // 1 cm/s
    const Eigen::Vector3d from = sphere ? Eigen::Vector3d(std::sin(along / 0.025),
                                                          -std::cos(along / 0.025), 0.0)
                                        : -Eigen::Vector3d::UnitY();
    FingerView& f = board.view.fingers[0];
    f = Touching(centre, from, -from);
    if (!sphere) {
      f.contact = centre + Eigen::Vector3d(along, -0.025, 0.0);
      f.tip = f.contact + 0.012 * from;
    }
    board.now = 0.01 * i;
    board.LearnSurface();
  }
  return board.flat_faces;
}

TEST(BlackboardTest, AnExplorerSlidingOverAFlatFaceFeelsItFlat) {
  const std::vector<FlatFace> faces = FlatFacesAfterASlide(Role::kExplore, false);
  ASSERT_EQ(faces.size(), 1u);  // once per slide, when it has gone 1.2 cm
  EXPECT_NEAR(faces[0].normal.dot(-Eigen::Vector3d::UnitY()), 1.0, 1e-9);
  EXPECT_NEAR(faces[0].point.y(), -0.025, 1e-9);  // on it, in the object's frame
  // Round a sphere the normal turns (0.5 rad over 1.2 cm): no face.
  EXPECT_TRUE(FlatFacesAfterASlide(Role::kExplore, true).empty());
  // A grip finger's contact moves in the object frame by the pose estimate's drift: not a slide.
  EXPECT_TRUE(FlatFacesAfterASlide(Role::kGrip, false).empty());
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
