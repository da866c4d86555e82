#include "components/controller/grasp_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

namespace dmpl {
namespace {

constexpr double kRadius = 0.025;  // the nominal sphere, m

// A contact on the sphere about the origin at polar angle `polar` from +z, azimuth `azimuth`.
SupportContact OnSphere(double polar, double azimuth) {
  const Eigen::Vector3d out(std::sin(polar) * std::cos(azimuth),
                            std::sin(polar) * std::sin(azimuth), std::cos(polar));
  return {kRadius * out, -out};
}

// The hand's grasp: four tips around the sphere's lower half, palm up (+z), the thumb opposite.
std::vector<SupportContact> FourFingerGrasp() {
  return {OnSphere(2.0, 0.0), OnSphere(2.0, 1.6), OnSphere(2.0, M_PI), OnSphere(2.2, 4.6)};
}

std::vector<SupportContact> Without(std::vector<SupportContact> c, size_t lifted) {
  c.erase(c.begin() + static_cast<long>(lifted));
  return c;
}

// Each force inside its (true, circular) friction cone and within the push limits; together
// they cancel the load and have no moment about the centre.
void ExpectHolds(const std::vector<SupportContact>& contacts, const SupportPlan& plan,
                 const Eigen::Vector3d& load, const SupportLimits& limits) {
  ASSERT_TRUE(plan.feasible);
  ASSERT_EQ(plan.forces.size(), contacts.size());
  Eigen::Vector3d net = load, moment = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < contacts.size(); ++i) {
    const Eigen::Vector3d& f = plan.forces[i];
    const Eigen::Vector3d n = contacts[i].normal.normalized();
    const double push = f.dot(n);
    const double sideways = (f - push * n).norm();
    EXPECT_LE(sideways, limits.friction * push + 1e-9) << "contact " << i;
    EXPECT_GE(push, limits.min_push_n - 1e-9);
    EXPECT_LE(push, limits.max_push_n + 1e-9);
    net += f;
    moment += contacts[i].point.cross(f);
  }
  // GLPK's simplex is exact to its feasibility tolerance (1e-7 relative).
  EXPECT_LT(net.norm(), 1e-6);
  EXPECT_LT(moment.norm(), 1e-7);
}

TEST(GraspSupportTest, ThreeFingersCarryTheWeightAlongAnyGravityWithTheFourthLifted) {
  // 200 g (1.96 N) along 200 random gravity directions, each finger lifted in turn: where the
  // three that stay can carry it (their support along gravity exceeds it), the plan does, inside
  // the friction cone; where they cannot, it says so instead of returning forces.
  const SupportLimits limits{0.8, 0.2, 6.0};
  const double weight = 0.2 * 9.81;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  int planned = 0, refused = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d gravity =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const auto lifted = static_cast<size_t>(trial % 4);
    const std::vector<SupportContact> three = Without(FourFingerGrasp(), lifted);
    const double support = SupportAlong(three, gravity, Eigen::Vector3d::Zero(), limits);
    const SupportPlan plan = PlanSupport(three, weight * gravity, Eigen::Vector3d::Zero(), limits);
    if (support > weight * 1.01) {
      ExpectHolds(three, plan, weight * gravity, limits);
      ++planned;
    } else if (support < weight * 0.99) {
      EXPECT_FALSE(plan.feasible) << "support " << support << " N";
      ++refused;
    }
  }
  // Both kinds occur: the test sees grasps that hold and grasps that cannot.
  EXPECT_GT(planned, 50);
  EXPECT_GT(refused, 10);
}

TEST(GraspSupportTest, PalmUpTheFourFingersCarryTheWeightWithTheLeastSqueeze) {
  const SupportLimits limits{1.0, 0.0, 6.0};
  const Eigen::Vector3d load(0, 0, -0.49);  // 50 g, palm up
  const SupportPlan plan = PlanSupport(FourFingerGrasp(), load, Eigen::Vector3d::Zero(), limits);
  ExpectHolds(FourFingerGrasp(), plan, load, limits);
  // Below the equator the normals alone lift it: the squeeze is of the order of the weight.
  EXPECT_LT(plan.total_push_n, 2.0 * 0.49);
}

TEST(GraspSupportTest, FingersAroundTheEquatorCarryByFrictionUpToTheirPushTimesFriction) {
  // Three tips at 120 deg on the equator, the weight along the axis: friction alone carries it,
  // so the support is 3 * friction * max push, less the pyramid's inscription (cos(pi / 8)).
  const std::vector<SupportContact> ring = {OnSphere(M_PI / 2, 0.0), OnSphere(M_PI / 2, 2.1),
                                            OnSphere(M_PI / 2, 4.2)};
  const SupportLimits limits{0.5, 0.0, 4.0};
  const double support = SupportAlong(ring, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(),
                                      limits);
  EXPECT_LE(support, 3 * 0.5 * 4.0 + 1e-9);
  EXPECT_GE(support, 3 * 0.5 * 4.0 * std::cos(M_PI / 8) - 1e-9);
}

TEST(GraspSupportTest, FingersOnOneSideCannotHoldAWeightPullingAwayFromThem) {
  // Three tips on the upper cap pushing down, gravity down: no push can lift the sphere.
  const std::vector<SupportContact> cap = {OnSphere(0.5, 0.0), OnSphere(0.5, 2.1),
                                           OnSphere(0.5, 4.2)};
  const SupportLimits limits{1.0, 0.0, 10.0};
  EXPECT_EQ(SupportAlong(cap, -Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), limits), 0.0);
  EXPECT_FALSE(
      PlanSupport(cap, Eigen::Vector3d(0, 0, -0.49), Eigen::Vector3d::Zero(), limits).feasible);
  // Turned over (palm down, the same tips now under the sphere), they hold it easily.
  EXPECT_GT(SupportAlong(cap, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), limits), 10.0);
}

TEST(GraspSupportTest, ALoadOffTheCentreNeedsTheMomentTooAndTwoOpposedPointsCannotGiveIt) {
  // Two opposed tips pinch the sphere at its equator: a weight through the centre is carried by
  // friction; the same weight acting 1 cm off the pinch line turns the sphere about it, which two
  // point contacts without spin friction cannot resist.
  const std::vector<SupportContact> pinch = {OnSphere(M_PI / 2, 0.0), OnSphere(M_PI / 2, M_PI)};
  const SupportLimits limits{1.0, 0.0, 5.0};
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
  EXPECT_GT(SupportAlong(pinch, down, Eigen::Vector3d::Zero(), limits), 5.0);
  EXPECT_EQ(SupportAlong(pinch, down, Eigen::Vector3d(0, 0.01, 0), limits), 0.0);
}

TEST(GraspSupportTest, NoContactsHoldNothing) {
  const SupportLimits limits;
  EXPECT_EQ(SupportAlong({}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), limits), 0.0);
  EXPECT_FALSE(PlanSupport({}, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), limits).feasible);
}

}  // namespace
}  // namespace dmpl
