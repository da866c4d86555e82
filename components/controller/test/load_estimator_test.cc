#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "components/controller/force_planner.h"
#include "components/controller/load_estimator.h"

namespace dmpl {
namespace {

// `count` contacts evenly around a 2.5 cm sphere, `tilt` below its equator (the palm normal x is
// up), with their true normals (into the object) as a fingertip's tactile reading gives them.
void SphereContacts(double tilt, std::vector<Eigen::Vector3d>* contacts,
                    std::vector<Eigen::Vector3d>* normals, const Eigen::Vector3d& centre,
                    int count = 4) {
  contacts->clear();
  normals->clear();
  for (int k = 0; k < count; ++k) {
    const double a = k * 2 * M_PI / count + 0.3;
    const Eigen::Vector3d out(-std::sin(tilt), std::cos(tilt) * std::cos(a),
                              std::cos(tilt) * std::sin(a));
    contacts->push_back(centre + 0.025 * out);
    normals->push_back(-out);
  }
}

TEST(NormalsMeetingPointTest, FindsTheSphereCentreWhereverTheContactsSit) {
  const Eigen::Vector3d centre(0.07, 0.004, 0.015);
  std::vector<Eigen::Vector3d> c, n;
  for (double tilt : {0.0, 0.3, 0.6}) {
    SphereContacts(tilt, &c, &n, centre);
    const auto p = NormalsMeetingPoint(c, n, {true, true, true, false}, centre + Eigen::Vector3d(0.005, 0, 0));
    ASSERT_TRUE(p.has_value());
    // Three lines through the centre pin it; the pull toward the fallback moves it < 10 um.
    EXPECT_LT((*p - centre).norm(), 1e-5) << "tilt " << tilt;
  }
}

TEST(NormalsMeetingPointTest, OpposedFingersLeaveTheirAxisToTheFallback) {
  const std::vector<Eigen::Vector3d> c = {{0.07, 0.02, 0.0}, {0.07, -0.02, 0.0}};
  const std::vector<Eigen::Vector3d> n = {{0, -1, 0}, {0, 1, 0}};
  const auto p = NormalsMeetingPoint(c, n, {true, true}, Eigen::Vector3d(0.07, 0.005, 0.0));
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR((*p)[1], 0.005, 1e-6);  // along the line: free, from the fallback
  EXPECT_NEAR((*p)[0], 0.07, 1e-6);
  EXPECT_NEAR((*p)[2], 0.0, 1e-6);
  EXPECT_FALSE(NormalsMeetingPoint({c[0]}, {n[0]}, {true}, c[0]).has_value());
}

TEST(PlanBoundedForcesTest, ContactsBelowTheEquatorCarryTheWeightAlongTheirNormals) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  std::vector<Eigen::Vector3d> c, n;
  SphereContacts(0.35, &c, &n, centre, 3);
  c.push_back(centre + Eigen::Vector3d(0.0, 0.0, 0.025));  // the explorer, out of the balance
  n.push_back(Eigen::Vector3d(0, 0, -1));
  const Eigen::Vector3d weight_carried(0.2 * 9.81, 0, 0);  // 200 g, palm up
  const std::vector<bool> grip = {true, true, true, false};
  const ForcePlan plan = PlanBoundedForces(c, grip, centre, 0.8, 0.4, 3.0, weight_carried);
  EXPECT_TRUE(plan.balanced);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    sum += plan.forces[k].magnitude * plan.forces[k].direction;
    EXPECT_LT(plan.forces[k].direction.cross(n[k]).norm(), 1e-9) << "along the normal";
    EXPECT_GE(plan.forces[k].magnitude, 0.4);
    EXPECT_LE(plan.forces[k].magnitude, 3.0);
  }
  EXPECT_LT((sum - weight_carried).norm(), 1e-3);
  EXPECT_EQ(plan.forces[3].magnitude, 0.0);
}

TEST(PlanBoundedForcesTest, BoundsHoldWhenTheLoadCannotBeCarried) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  std::vector<Eigen::Vector3d> c, n;
  SphereContacts(0.1, &c, &n, centre);  // nearly at the equator: little support along x
  const ForcePlan heavy =
      PlanBoundedForces(c, {true, true, true, true}, centre, 0.8, 0.4, 2.0, {5.0, 0, 0});
  EXPECT_FALSE(heavy.balanced);
  for (const auto& f : heavy.forces) EXPECT_NEAR(f.magnitude, 2.0, 1e-9);  // all at the cap
  // No load: forces along normals below the equator all push the object up; the least they can
  // push is the minimum each.
  const ForcePlan none =
      PlanBoundedForces(c, {true, true, true, true}, centre, 0.8, 0.4, 2.0, Eigen::Vector3d::Zero());
  EXPECT_FALSE(none.balanced);
  for (const auto& f : none.forces) EXPECT_NEAR(f.magnitude, 0.4, 1e-9);
}

TEST(PlanBoundedForcesTest, AtTheEquatorTheSqueezeStaysNominal) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  std::vector<Eigen::Vector3d> c, n;
  SphereContacts(0.0, &c, &n, centre);
  const ForcePlan plan =
      PlanBoundedForces(c, {true, true, true, true}, centre, 0.8, 0.4, 3.0, Eigen::Vector3d::Zero());
  EXPECT_TRUE(plan.balanced);
  for (const auto& f : plan.forces) EXPECT_NEAR(f.magnitude, 0.8, 1e-6);
}

TEST(LoadEstimatorTest, ASinkingObjectTeachesTheLoadWhichIsKeptAndBounded) {
  LoadParams p;
  p.enabled = true;
  p.proportional_gain = 40.0;
  p.integral_gain = 800.0;
  p.max_load_n = 2.5;
  p.max_net_force_n = 3.0;
  p.gravity_direction = {0.0, 0.0, 0.0};  // every direction
  LoadEstimator load(p);
  const Eigen::Vector3d sunk(0.002, 0, 0);  // 2 mm below its reference (x is up)
  Eigen::Vector3d net;
  for (int k = 0; k < 100; ++k) net = load.Update(0.001, sunk, true);
  EXPECT_NEAR(load.load().x(), 800.0 * 0.1 * 0.002, 1e-9);  // 0.16 N after 0.1 s
  EXPECT_NEAR(net.x(), 0.16 + 40.0 * 0.002, 1e-9);
  // Grasp lost: nothing learned, what was learned is kept.
  EXPECT_NEAR(load.Update(0.001, Eigen::Vector3d(0.05, 0, 0), false).x(), 0.16, 1e-9);
  for (int k = 0; k < 100000; ++k) net = load.Update(0.001, sunk, true);
  EXPECT_NEAR(load.load().norm(), 2.5, 1e-9);
  EXPECT_NEAR(net.norm(), 2.58, 1e-9);
  p.gravity_direction = {-9.81, 0.0, 0.0};
  // Along gravity only (palm up: -x): the camera's noise across it teaches nothing.
  LoadEstimator along{p};
  for (int k = 0; k < 100; ++k) net = along.Update(0.001, Eigen::Vector3d(0.002, 0.003, -0.001), true);
  EXPECT_NEAR(along.load().x(), 0.16, 1e-9);
  EXPECT_EQ(along.load().y(), 0.0);
  EXPECT_EQ(along.load().z(), 0.0);
  // Off: no load at all.
  LoadEstimator off{LoadParams{}};
  EXPECT_EQ(off.Update(0.001, sunk, true), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace dmpl
