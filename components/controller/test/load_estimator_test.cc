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
  p.deadband_m = 0.0005;
  p.reference_follow_s = 0.0;  // a fixed reference
  p.max_load_n = 2.5;
  p.max_net_force_n = 3.0;
  const Eigen::Vector3d gravity(-1, 0, 0);  // palm up
  LoadEstimator load(p, gravity);
  const Eigen::Vector3d start(0.07, 0.0, 0.015);
  load.Update(0.001, start, true);  // the reference
  // 2.5 mm down (2 mm beyond the deadband) and sideways, which teaches nothing: the load is
  // along gravity only.
  const Eigen::Vector3d sunk = start + Eigen::Vector3d(-0.0025, 0.003, -0.001);
  Eigen::Vector3d net;
  for (int k = 0; k < 100; ++k) net = load.Update(0.001, sunk, true);
  EXPECT_NEAR(load.load_n(), 800.0 * 0.1 * 0.002, 1e-9);  // 0.16 N after 0.1 s
  EXPECT_NEAR(net.x(), 0.16 + 40.0 * 0.002, 1e-9);
  EXPECT_EQ(net.y(), 0.0);
  EXPECT_EQ(net.z(), 0.0);
  // Grasp lost: nothing learned, what was learned is kept.
  EXPECT_NEAR(load.Update(0.001, start - Eigen::Vector3d(0.05, 0, 0), false).x(), 0.16, 1e-9);
  load.Update(0.001, sunk, true);  // holding again: a new reference where the object is now
  for (int k = 0; k < 1000; ++k) net = load.Update(0.001, sunk, true);
  EXPECT_NEAR(load.load_n(), 0.16, 1e-9) << "an object that stays put teaches nothing";
  for (int k = 0; k < 100000; ++k) net = load.Update(0.001, sunk - Eigen::Vector3d(0.01, 0, 0), true);
  EXPECT_NEAR(load.load_n(), 2.5, 1e-9);
  EXPECT_NEAR(net.x(), 2.5 + 40.0 * 0.0095, 1e-9);
}

TEST(LoadEstimatorTest, TheReferenceFollowsSoOnlySinkingTeaches) {
  LoadParams p;
  p.enabled = true;
  p.proportional_gain = 0.0;
  p.integral_gain = 1000.0;
  p.deadband_m = 0.0;
  p.reference_follow_s = 0.1;
  LoadEstimator load(p, Eigen::Vector3d(-1, 0, 0));
  Eigen::Vector3d x(0.07, 0, 0);
  load.Update(0.001, x, true);
  x.x() -= 0.002;  // a 2 mm step down, then still
  for (int k = 0; k < 2000; ++k) load.Update(0.001, x, true);
  // The error decays with the follower: the load learned is ki * step * tau (0.2 N).
  EXPECT_NEAR(load.load_n(), 1000.0 * 0.002 * 0.1, 0.01);
  const double learned = load.load_n();
  for (int k = 0; k < 2000; ++k) load.Update(0.001, x, true);
  EXPECT_NEAR(load.load_n(), learned, 1e-6) << "once it stopped sinking, the load stays";
  // Off: no load at all.
  LoadEstimator off(LoadParams{}, Eigen::Vector3d(-1, 0, 0));
  EXPECT_EQ(off.Update(0.001, x, true), Eigen::Vector3d::Zero());
}

TEST(PlanBoundedForcesTest, ALoneFingerIsKeptLightAndGravityIsLeftToFriction) {
  // R explores: F (at +y) has no opposite. With a moderate balance weight T and M keep their
  // squeeze and F goes light, instead of all three easing off to cancel F's push.
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  const std::vector<Eigen::Vector3d> c = {centre + Eigen::Vector3d(0, 0, -0.025),
                                          centre + Eigen::Vector3d(0, 0.025, 0),
                                          centre + Eigen::Vector3d(0, 0, 0.025),
                                          centre + Eigen::Vector3d(0, -0.025, 0)};
  const std::vector<bool> grip = {true, true, true, false};
  const ForcePlan plan = PlanBoundedForces(c, grip, centre, 0.8, 0.1, 2.5, Eigen::Vector3d::Zero(),
                                           10.0);
  EXPECT_NEAR(plan.forces[0].magnitude, 0.8, 1e-9);
  EXPECT_NEAR(plan.forces[2].magnitude, 0.8, 1e-9);
  // F's least-squares compromise, 10 f^2 + (f - 0.8)^2 at f = 0.8 / 11, lies below the minimum.
  EXPECT_NEAR(plan.forces[1].magnitude, 0.1, 1e-9);
  // The weight asked along gravity, which these equatorial normals cannot give, changes nothing
  // when gravity is left to friction.
  const ForcePlan weighed = PlanBoundedForces(c, {true, true, true, true}, centre, 0.8, 0.1, 2.5,
                                              Eigen::Vector3d(2.0, 0, 0), 10.0,
                                              Eigen::Vector3d(-1, 0, 0));
  for (const auto& f : weighed.forces) EXPECT_NEAR(f.magnitude, 0.8, 1e-9);
  EXPECT_TRUE(weighed.balanced);  // across gravity, which is all it was asked
}

}  // namespace
}  // namespace dmpl
