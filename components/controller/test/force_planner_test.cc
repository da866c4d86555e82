#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

// An ellipsoid held by two fingers whose normals are 5 deg from opposed and miss each other by
// 1 cm: their lines meet ~10 cm out, where a finger sent to regain its contact leaves the object;
// the estimate stands instead. Where the lines meet at a sphere's centre, that point stands.
TEST(CentreWithinReachTest, WhereSkewNormalsMeetFarOutTheEstimateStands) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  const double tilt = 5.0 * M_PI / 180.0;
  const std::vector<Eigen::Vector3d> c = {centre + Eigen::Vector3d(0.005, 0.025, 0.001),
                                          centre + Eigen::Vector3d(-0.005, -0.025, -0.001)};
  const std::vector<Eigen::Vector3d> n = {{std::sin(tilt), -std::cos(tilt), 0.0}, {0.0, 1.0, 0.0}};
  const Eigen::Vector3d estimate = centre + Eigen::Vector3d(0.002, 0.0, 0.0);
  const auto meet = NormalsMeetingPoint(c, n, {true, true}, estimate);
  ASSERT_TRUE(meet.has_value());
  EXPECT_GT((*meet - centre).norm(), 0.08);
  EXPECT_EQ(CentreWithinReach(*meet, estimate, c, {true, true}), estimate);
  std::vector<Eigen::Vector3d> sc, sn;
  SphereContacts(0.3, &sc, &sn, centre);
  const std::vector<bool> grip = {true, true, true, false};
  const auto sphere = NormalsMeetingPoint(sc, sn, grip, estimate);
  EXPECT_EQ(CentreWithinReach(*sphere, estimate, sc, grip), *sphere);
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

// The cost PlanBoundedForces minimises, and its minimum by brute force: a fine grid descent

// from every corner would be slow; instead every assignment of each force to free / minimum /

// maximum is solved and the cheapest that stays in the box is kept (no KKT shortcut).

double PlanCost(const Eigen::Matrix3Xd& u, const Eigen::VectorXd& f, const Eigen::Vector3d& net,
                double w, double nominal) {
  return w * (u * f - net).squaredNorm() + (f.array() - nominal).matrix().squaredNorm();
}

double BruteForceMinimum(const Eigen::Matrix3Xd& u, const Eigen::Vector3d& net, double w,
                         double nominal, double lo, double hi) {
  const int n = static_cast<int>(u.cols());
  double best = std::numeric_limits<double>::infinity();
  std::vector<int> state(n, 0);
  for (;;) {
    Eigen::VectorXd f(n);
    std::vector<int> free;
    for (int k = 0; k < n; ++k) {
      if (state[k] == 0) free.push_back(k); else f[k] = state[k] == 1 ? lo : hi;
    }
    bool inside = true;
    if (!free.empty()) {
      const int m = static_cast<int>(free.size());
      Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 + m, m);
      Eigen::VectorXd b(3 + m);
      Eigen::Vector3d rhs = net;
      for (int k = 0; k < n; ++k) if (state[k] != 0) rhs -= f[k] * u.col(k);
      for (int j = 0; j < m; ++j) a.block<3, 1>(0, j) = std::sqrt(w) * u.col(free[j]);
      a.bottomRows(m).setIdentity();
      b.head<3>() = std::sqrt(w) * rhs;
      b.tail(m).setConstant(nominal);
      const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
      for (int j = 0; j < m; ++j) {
        f[free[j]] = x[j];
        inside = inside && x[j] >= lo - 1e-9 && x[j] <= hi + 1e-9;
      }
    }
    if (inside) best = std::min(best, PlanCost(u, f, net, w, nominal));
    int k = 0;
    while (k < n && ++state[k] == 3) state[k++] = 0;
    if (k == n) break;
  }
  return best;
}

TEST(PlanBoundedForcesTest, FindsTheOptimumOfRandomProblems) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector3d aim(0.07, 0.0, 0.015);
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 2 + trial % 3;
    std::vector<Eigen::Vector3d> c;
    for (int k = 0; k < n; ++k) {
      c.push_back(aim + 0.025 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized());
    }
    const Eigen::Vector3d net(unit(rng), unit(rng), unit(rng));
    const double w = trial % 2 ? 10.0 : 1e4;
    const ForcePlan plan =
        PlanBoundedForces(c, std::vector<bool>(n, true), aim, 0.8, 0.1, 2.5, net, w);
    Eigen::Matrix3Xd u(3, n);
    Eigen::VectorXd f(n);
    for (int k = 0; k < n; ++k) {
      u.col(k) = plan.forces[k].direction;
      f[k] = plan.forces[k].magnitude;
      ASSERT_GE(f[k], 0.1 - 1e-12);
      ASSERT_LE(f[k], 2.5 + 1e-12);
    }
    const double best = BruteForceMinimum(u, net, w, 0.8, 0.1, 2.5);
    ASSERT_LE(PlanCost(u, f, net, w, 0.8), best * (1 + 1e-9) + 1e-12) << "trial " << trial;
  }
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

// A capsule along y (r 2 cm, its cylinder 6 cm long): the thumb below and the middle finger above
// pinch its side, the ring finger pushes on one cap, the fore finger (on the other cap) explores.
// The three normals' lines meet 4 cm below the thumb: aimed there the thumb would pull and the
// plan eases the whole grip; kept within the friction cone, the pinch holds.
TEST(AimWithinConesTest, APinchAcrossACapsuleKeepsItsSqueezeWhileAPushOnACapIsEased) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.02);
  const Eigen::Vector3d cap = centre + Eigen::Vector3d(0, -0.03, 0);
  const Eigen::Vector3d out(0, -0.5, std::sqrt(3.0) / 2);  // the ring finger's, from its cap
  const std::vector<Eigen::Vector3d> c = {centre + Eigen::Vector3d(0, 0.005, -0.02),
                                          centre + Eigen::Vector3d(0, 0.03 + 0.02, 0),
                                          centre + Eigen::Vector3d(0, 0.005, 0.02),
                                          cap + 0.02 * out};
  const std::vector<Eigen::Vector3d> n = {{0, 0, 1}, {0, -1, 0}, {0, 0, -1}, -out};
  const std::vector<bool> grip = {true, false, true, true};
  const auto meet = NormalsMeetingPoint(c, n, grip, centre);
  ASSERT_TRUE(meet.has_value());
  EXPECT_LT((*meet)[2], c[0][2] - 0.03) << "the lines meet well behind the thumb";
  const auto plan_along = [&](double max_off) {
    return PlanBoundedForcesAlong(AimWithinCones(c, n, grip, *meet, max_off), grip, *meet, 2.0,
                                  0.1, 2.5, Eigen::Vector3d::Zero());
  };
  const ForcePlan aimed = plan_along(M_PI);  // aimed at the meeting point, as before
  EXPECT_LT(aimed.forces[0].direction.dot(n[0]), 0.0) << "the thumb would pull";
  EXPECT_LT(aimed.forces[0].magnitude + aimed.forces[2].magnitude, 1.0) << "the pinch eased";
  const double cone = 0.35;
  const ForcePlan kept = plan_along(cone);
  for (int k : {0, 2, 3}) {
    EXPECT_LE(std::acos(kept.forces[k].direction.dot(n[k])), cone + 1e-9) << k;
  }
  EXPECT_GT(kept.forces[0].magnitude, 1.5);
  EXPECT_GT(kept.forces[2].magnitude, 1.5);
  EXPECT_LT(kept.forces[3].magnitude, 0.5) << "nothing opposes the push on the cap";
  EXPECT_EQ(kept.forces[1].magnitude, 0.0) << "the explorer stays out";
  // On a sphere the normals meet at its centre and the cone changes nothing.
  std::vector<Eigen::Vector3d> sc, sn;
  SphereContacts(0.3, &sc, &sn, centre);
  const std::vector<bool> all(sc.size(), true);
  const auto directions = AimWithinCones(sc, sn, all, centre, cone);
  for (size_t k = 0; k < sc.size(); ++k) {
    EXPECT_LT((directions[k] - (centre - sc[k]).normalized()).norm(), 1e-12);
  }
}

TEST(PlanBoundedForcesTest, APairSlightlyOffFacingKeepsItsSqueezeWhenFrictionTakesASmallShare) {
  // The thumb explores; the middle finger across from it has no opposite; the fore and ring
  // fingers face each other 4 deg off the line between them, both leaning toward the palm (-x),
  // so their pushes at 2 N add 0.28 N along -x. Balanced exactly, the pair has to go down to its
  // minimum; with 0.3 N a side left to friction it keeps its squeeze and the middle finger is
  // still eased.
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  const double r = 0.025, lean = 4.0 * M_PI / 180.0;
  const std::vector<Eigen::Vector3d> c = {
      centre + Eigen::Vector3d(0, 0, -r),
      centre + r * Eigen::Vector3d(std::sin(lean), std::cos(lean), 0),
      centre + Eigen::Vector3d(0, 0, r),
      centre + r * Eigen::Vector3d(std::sin(lean), -std::cos(lean), 0)};
  const std::vector<bool> grip = {false, true, true, true};
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  const ForcePlan exact =
      PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5, none, 1e4, none, FrictionShare{});
  const ForcePlan shared =
      PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5, none, 1e4, none, FrictionShare{0.3});
  EXPECT_LT(exact.forces[1].magnitude, 0.11);
  EXPECT_LT(exact.forces[2].magnitude, 0.11);
  EXPECT_GT(shared.forces[1].magnitude, 1.99);
  EXPECT_NEAR(shared.forces[1].magnitude, shared.forces[3].magnitude, 1e-9);
  EXPECT_LT(shared.forces[2].magnitude, 0.31);  // the middle finger's unopposed push
  EXPECT_EQ(shared.forces[0].magnitude, 0.0);   // the explorer takes no part
  EXPECT_TRUE(shared.balanced);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& f : shared.forces) sum += f.magnitude * f.direction;
  EXPECT_LE(sum.cwiseAbs().maxCoeff(), 0.3 + 1e-3) << "no more than friction's share";
  // Without the share the default arguments give the same plan as a share of 0.
  const ForcePlan defaults = PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5, none);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(defaults.forces[k].magnitude, exact.forces[k].magnitude);
}

// The weight along gravity: a finger below the object, one on top, one at its side (the fourth
// explores), the palm sideways. Left to friction (the plan of before) the finger on top pushes
// down as hard as the one below pushes up and the side finger's friction would have to carry the
// whole weight; with the balance along gravity within friction's share, the pushes hold it.
TEST(PlanBoundedForcesTest, ThePushesCarryTheWeightWhereFrictionCannot) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  const double r = 0.025;
  for (const Eigen::Vector3d& gravity : {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, -1, 0),
                                         Eigen::Vector3d(1, 1, -1).normalized()}) {
    const Eigen::Vector3d up = -gravity;
    const Eigen::Vector3d side = up.unitOrthogonal();
    // Below (pushes up), at the side, on top (pushes down), exploring.
    const std::vector<Eigen::Vector3d> c = {centre - r * up, centre + r * side, centre + r * up,
                                            centre - r * side};
    const std::vector<bool> grip = {true, true, true, false};
    const double weight = 1.96;  // 200 g
    const Eigen::Vector3d held = weight * up;
    const ForcePlan left = PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5, held, 10.0, gravity);
    const FrictionShare share{0.0, 0.05, 0.5};
    // The balance exact (a large weight), and as the controller weighs it (10).
    const ForcePlan carried =
        PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5, held, 1e4, gravity, share);
    const ForcePlan weighed =
        PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5, held, 10.0, gravity, share);
    const auto along_up = [&](const ForcePlan& plan) {
      double sum = 0.0;
      for (const auto& f : plan.forces) sum += f.magnitude * f.direction.dot(up);
      return sum;
    };
    EXPECT_LT(along_up(left), 0.2) << "left to friction, the pushes hold nothing up";
    // The pair along gravity has no friction along it, and the level side finger's push has no
    // part along it to leave to its friction: the pushes hold all of the weight.
    EXPECT_NEAR(along_up(carried), weight, 1e-3);
    EXPECT_GT(along_up(weighed), 1.5);
    EXPECT_GT(weighed.forces[0].magnitude - weighed.forces[2].magnitude, 1.5);
    for (const auto& f : carried.forces) EXPECT_LE(f.magnitude, 2.5 + 1e-9);
  }
}

// Pushes near level that lean a little along gravity (contacts a few millimetres off the
// equator, palm down) are their own friction's: the balance along gravity does not ease them.
TEST(PlanBoundedForcesTest, LevelPushesLeaningAlongGravityKeepTheirSqueeze) {
  const Eigen::Vector3d centre(0.07, 0.0, 0.015);
  std::vector<Eigen::Vector3d> c, n;
  SphereContacts(0.25, &c, &n, centre, 4);  // 0.25 rad toward the palm off the equator
  const Eigen::Vector3d gravity(1, 0, 0);     // palm down: away from the palm
  const std::vector<bool> grip(4, true);
  const ForcePlan left = PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5,
                                           Eigen::Vector3d::Zero(), 10.0, gravity);
  const ForcePlan carried = PlanBoundedForces(c, grip, centre, 2.0, 0.1, 2.5,
                                              Eigen::Vector3d::Zero(), 10.0, gravity,
                                              FrictionShare{0.0, 0.05, 0.5});
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(carried.forces[k].magnitude, left.forces[k].magnitude, 1e-6);
    EXPECT_NEAR(carried.forces[k].magnitude, 2.0, 1e-6);
  }
  // Leaning further (0.7 rad: steeper than asin 0.5) they are eased toward the balance.
  std::vector<Eigen::Vector3d> steep, steep_n;
  SphereContacts(0.7, &steep, &steep_n, centre, 4);
  const ForcePlan eased = PlanBoundedForces(steep, grip, centre, 2.0, 0.1, 2.5,
                                            Eigen::Vector3d::Zero(), 10.0, gravity,
                                            FrictionShare{0.0, 0.05, 0.5});
  for (int k = 0; k < 4; ++k) EXPECT_LT(eased.forces[k].magnitude, 1.0);
}

}  // namespace
}  // namespace dmpl
