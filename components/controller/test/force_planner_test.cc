#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

#include "components/controller/force_planner.h"

namespace dmpl {
namespace {

void ExpectBalanced(const std::vector<Eigen::Vector3d>& p, const std::vector<bool>& grip,
                    double nominal, double minimum) {
  const ForcePlan plan = PlanGripForces(p, grip, nominal, minimum);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < p.size(); ++i) {
    if (!grip[i]) {
      EXPECT_EQ(plan.forces[i].magnitude, 0.0) << "exploration finger stays out of the balance";
      continue;
    }
    const Eigen::Vector3d f = plan.forces[i].magnitude * plan.forces[i].direction;
    force += f;
    moment += p[i].cross(f);  // about the palm origin: any point works when the net force is 0
    EXPECT_GE(plan.forces[i].magnitude, minimum - 1e-12);
    // Every force points at the centroid.
    EXPECT_LT((plan.centroid - p[i]).normalized().cross(plan.forces[i].direction).norm(), 1e-9);
  }
  EXPECT_TRUE(plan.balanced);
  EXPECT_LT(force.norm(), 1e-9);
  EXPECT_LT(moment.norm(), 1e-9);
}

TEST(ForcePlannerTest, ThreeAndFourContactsAreBalanced) {
  // The paper's grasp layout: thumb below, three fingers above, around a sphere.
  const std::vector<Eigen::Vector3d> four = {{0.09, 0.018, -0.012}, {0.09, 0.028, 0.044},
                                             {0.09, 0.0, 0.057}, {0.09, -0.028, 0.044}};
  ExpectBalanced(four, {true, true, true, true}, 0.8, 0.4);
  ExpectBalanced(four, {true, true, true, false}, 0.8, 0.4);  // R explores
  ExpectBalanced({four[0], four[1], four[2]}, {true, true, true}, 0.8, 0.4);
}

TEST(ForcePlannerTest, RandomContactsAreBalancedAboveTheMinimum) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 0.03);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Eigen::Vector3d> p(4);
    for (auto& x : p) x = Eigen::Vector3d(n(rng), n(rng), n(rng));
    std::vector<bool> grip = {true, true, true, trial % 2 == 0};
    ExpectBalanced(p, grip, 1.0, 0.5);
  }
}

TEST(ForcePlannerTest, SymmetricContactsGetTheNominalForce) {
  const std::vector<Eigen::Vector3d> p = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  const ForcePlan plan = PlanGripForces(p, {true, true, true, true}, 0.8, 0.4);
  for (const auto& f : plan.forces) EXPECT_NEAR(f.magnitude, 0.8, 1e-12);
}

TEST(ForcePlannerTest, FewerThanTwoGripContactsIsNotABalance) {
  const ForcePlan plan = PlanGripForces({{1, 0, 0}, {0, 1, 0}}, {true, false}, 0.8, 0.4);
  EXPECT_FALSE(plan.balanced);
}

}  // namespace
}  // namespace dmpl
