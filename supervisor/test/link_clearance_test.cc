// A link's clearance from the surface the fingertips have felt: a sphere felt all round, a face,
// and a side never touched.
#include <gtest/gtest.h>

#include <cmath>

#include "supervisor/link_clearance.h"
#include "supervisor/test/felt_objects.h"

namespace dmpl {
namespace {

constexpr double kRadius = 0.025;

Eigen::Isometry3d ObjectPose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -1, 2).normalized()).matrix();
  pose.translation() = Eigen::Vector3d(0.08, 0.01, 0.02);
  return pose;
}

// Contacts all over a sphere of kRadius, or only where x > `min_x` in the object's frame; taken
// with the object at `pose`.
SurfaceModel FeltSphere(const Eigen::Isometry3d& pose, double min_x = -1.0) {
  return testing::FeltSphere(pose, kRadius, 600, min_x);
}

// A link (points every 1 mm along a 3 cm segment, and `radius`: a row of spheres) whose axis
// passes `closest` m from the centre at its middle, perpendicular to the direction to it (object
// frame, then placed with `pose`).
LinkSolid Across(const Eigen::Isometry3d& pose, const Eigen::Vector3d& direction, double closest,
                 double radius) {
  const Eigen::Vector3d d = direction.normalized();
  const Eigen::Vector3d along = d.unitOrthogonal();
  LinkSolid link;
  for (int i = -15; i <= 15; ++i) link.points.push_back(pose * (closest * d + 0.001 * i * along));
  link.radius = radius;
  return link;
}

TEST(LinkClearanceTest, ALinkBesideAFeltSphereAndOneThatReachesIntoIt) {
  const Eigen::Isometry3d pose = ObjectPose();
  const SurfaceModel sphere = FeltSphere(pose);
  const Eigen::Vector3d toward(0.3, -0.5, 0.8);
  // Its axis 35 mm from the centre, 4 mm thick: 6 mm off the surface at its middle.
  const auto beside = SurfaceClearance(Across(pose, toward, 0.035, 0.004), sphere, pose);
  ASSERT_TRUE(beside.has_value());
  EXPECT_NEAR(*beside, 0.006, 5e-4);
  // 15 mm from the centre: 14 mm inside.
  const auto inside = SurfaceClearance(Across(pose, toward, 0.015, 0.004), sphere, pose);
  ASSERT_TRUE(inside.has_value());
  EXPECT_NEAR(*inside, -0.014, 5e-4);
}

TEST(LinkClearanceTest, ASideNeverTouchedGivesNoVerdict) {
  const Eigen::Isometry3d pose = ObjectPose();
  const SurfaceModel half = FeltSphere(pose, 0.3);  // touched only where x > 0.3 (of the radius)
  EXPECT_FALSE(SurfaceClearance(Across(pose, -Eigen::Vector3d::UnitX(), 0.03, 0.004), half, pose)
                   .has_value());
  EXPECT_TRUE(SurfaceClearance(Across(pose, Eigen::Vector3d::UnitX(), 0.03, 0.004), half, pose)
                  .has_value());
}

// A face (x = 25 mm) felt over 4 x 4 cm; a link lying parallel to it 10 mm out, seen from the
// centre 8 to 30 deg off the face's normal: its clearance is the plane's distance, not the
// (longer) distance along the direction from the centre (7.1 mm at its nearest end).
TEST(LinkClearanceTest, ALinkAlongAFeltFaceStandsItsDistanceFromThePlane) {
  const Eigen::Isometry3d pose = ObjectPose();
  SurfaceModel face;
  for (double y = -0.02; y <= 0.02 + 1e-9; y += 0.003) {
    for (double z = -0.02; z <= 0.02 + 1e-9; z += 0.003) {
      face.Add(pose, pose * Eigen::Vector3d(kRadius, y, z),
               pose.linear() * Eigen::Vector3d::UnitX(), 0.0);
    }
  }
  LinkSolid link;
  for (double y = 0.005; y <= 0.02 + 1e-9; y += 0.005) {
    link.points.push_back(pose * Eigen::Vector3d(0.035, y, 0.0));
  }
  link.radius = 0.003;
  const auto clearance = SurfaceClearance(link, face, pose);
  ASSERT_TRUE(clearance.has_value());
  EXPECT_NEAR(*clearance, 0.007, 5e-5);
}

}  // namespace
}  // namespace dmpl
