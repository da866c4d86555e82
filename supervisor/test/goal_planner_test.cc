#include <gtest/gtest.h>

#include <cmath>

#include "components/runtime/params.h"
#include "supervisor/goal_planner.h"

namespace dmpl {
namespace {

Eigen::Quaterniond Turn(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

TEST(RotationToGoal, GivesTheAxisAndAngleThatTakeOneOrientationToTheOther) {
  const Eigen::Quaterniond from = Turn(0.7, {1, 2, 3});
  const Eigen::Vector3d axis = Eigen::Vector3d(-1, 0.5, 2).normalized();
  const Eigen::Quaterniond to = Turn(1.1, axis) * from;
  const AxisAngle r = RotationToGoal(from, to);
  EXPECT_NEAR(r.angle, 1.1, 1e-12);
  EXPECT_NEAR((r.axis - axis).norm(), 0.0, 1e-12);
  // Applying it (in the palm frame, on the left) lands on the goal.
  const Eigen::Quaterniond there = Turn(r.angle, r.axis) * from;
  EXPECT_NEAR(there.angularDistance(to), 0.0, 1e-12);
}

TEST(RotationToGoal, TakesTheShortWayEvenWhenTheQuaternionSignsDiffer) {
  const Eigen::Quaterniond from = Turn(0.2, Eigen::Vector3d::UnitZ());
  Eigen::Quaterniond to = Turn(-0.3, Eigen::Vector3d::UnitZ());
  to.coeffs() = -to.coeffs();  // the same rotation, the other hemisphere
  const AxisAngle r = RotationToGoal(from, to);
  EXPECT_NEAR(r.angle, 0.5, 1e-12);
  EXPECT_NEAR(r.axis.z(), -1.0, 1e-12);
  // 1.5 pi one way is 0.5 pi the other.
  const AxisAngle long_way = RotationToGoal(Eigen::Quaterniond::Identity(),
                                            Turn(1.5 * M_PI, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(long_way.angle, 0.5 * M_PI, 1e-12);
  EXPECT_NEAR(long_way.axis.x(), -1.0, 1e-12);
}

TEST(RotationToGoal, NearHalfATurnAndAtNoTurnIsStillAUnitAxis) {
  for (double angle : {M_PI - 1e-9, M_PI, 1e-13, 0.0}) {
    const AxisAngle r = RotationToGoal(Eigen::Quaterniond::Identity(),
                                       Turn(angle, Eigen::Vector3d(0, 1, 1)));
    EXPECT_NEAR(r.angle, angle, 1e-9) << angle;
    EXPECT_NEAR(r.axis.norm(), 1.0, 1e-12) << angle;
    EXPECT_LE(r.angle, M_PI);
  }
}

TEST(RandomGoals, AreSeededAndKeepTheirDistanceFromTheOneBefore) {
  const Eigen::Quaterniond start = Turn(0.3, {0, 0, 1});
  const auto a = RandomGoals(7, 200, M_PI / 2, start);
  const auto b = RandomGoals(7, 200, M_PI / 2, start);
  const auto c = RandomGoals(8, 200, M_PI / 2, start);
  ASSERT_EQ(a.size(), 200u);
  EXPECT_GE(RotationToGoal(start, a[0]).angle, M_PI / 2);
  double differs = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].coeffs(), b[i].coeffs());
    EXPECT_NEAR(a[i].norm(), 1.0, 1e-12);
    if (i > 0) {
      EXPECT_GE(RotationToGoal(a[i - 1], a[i]).angle, M_PI / 2);
    }
    differs += RotationToGoal(a[i], c[i]).angle;
  }
  EXPECT_GT(differs, 1.0);  // another seed, other goals
}

TEST(RandomGoals, CoverTheRotationsEvenly) {
  // Uniform over SO(3): the angle from the identity has density (1 - cos t) / pi, so its mean is
  // pi/2 + 2/pi (about 2.2 rad), and a quarter of the goals lie within 1.7663 rad (where
  // (t - sin t) / pi = 0.25).
  const auto goals = RandomGoals(3, 20000, 0.0, Eigen::Quaterniond::Identity());
  double mean = 0.0;
  int within = 0;
  for (const auto& q : goals) {
    const double t = RotationToGoal(Eigen::Quaterniond::Identity(), q).angle;
    mean += t / goals.size();
    within += t < 1.7663;
  }
  EXPECT_NEAR(mean, M_PI / 2 + 2 / M_PI, 0.02);
  EXPECT_NEAR(within / 20000.0, 0.25, 0.01);
}

TEST(GoalSequence, ReachesAGoalAfterHoldingWithinTheTolerance) {
  const Eigen::Quaterniond g1 = Turn(1.0, {1, 0, 0}), g2 = Turn(2.0, {0, 1, 0});
  GoalSequence goals({g1, g2}, 0.4, 0.5, 30.0);
  goals.Start(0.0);
  EXPECT_EQ(goals.Update(1.0, Turn(0.5, {1, 0, 0})), GoalSequence::Event::kNone);  // 0.5 away
  EXPECT_NEAR(goals.error_rad(), 0.5, 1e-12);
  EXPECT_EQ(goals.Update(2.0, Turn(0.7, {1, 0, 0})), GoalSequence::Event::kNone);  // within
  EXPECT_EQ(goals.Update(2.3, Turn(1.5, {1, 0, 0})), GoalSequence::Event::kNone);  // out again
  EXPECT_EQ(goals.Update(2.4, Turn(0.9, {1, 0, 0})), GoalSequence::Event::kNone);
  EXPECT_EQ(goals.Update(2.8, g1), GoalSequence::Event::kNone);  // 0.4 s within
  EXPECT_EQ(goals.Update(2.9, g1), GoalSequence::Event::kReached);
  EXPECT_EQ(goals.reached(), 1);
  EXPECT_NEAR(goals.times_s()[0], 2.9, 1e-12);
  EXPECT_EQ(goals.current().coeffs(), g2.coeffs());
  EXPECT_FALSE(goals.complete());
  EXPECT_EQ(goals.Update(3.0, g2), GoalSequence::Event::kNone);
  EXPECT_EQ(goals.Update(3.5, g2), GoalSequence::Event::kReached);
  EXPECT_NEAR(goals.times_s()[1], 0.6, 1e-12);
  EXPECT_TRUE(goals.complete());
  EXPECT_EQ(goals.Update(4.0, g1), GoalSequence::Event::kNone);  // nothing after the last
}

TEST(GoalSequence, AGoalNotReachedInTimeEndsTheSequence) {
  GoalSequence goals({Turn(2.0, {0, 0, 1}), Turn(0.0, {0, 0, 1})}, 0.4, 0.5, 10.0);
  goals.Start(5.0);
  EXPECT_EQ(goals.Update(14.9, Eigen::Quaterniond::Identity()), GoalSequence::Event::kNone);
  EXPECT_EQ(goals.Update(15.1, Eigen::Quaterniond::Identity()), GoalSequence::Event::kTimedOut);
  EXPECT_TRUE(goals.timed_out());
  EXPECT_EQ(goals.reached(), 0);
  EXPECT_EQ(goals.Update(16.0, Turn(2.0, {0, 0, 1})), GoalSequence::Event::kNone);
}

struct Holder {
  AxisParam axis;
  std::vector<OrientationParam> goals;
  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(axis));
    a->Visit(DMPL_NVP(goals));
  }
};

Holder Read(const std::string& yaml) {
  Holder h;
  YamlReadArchive::Load(YAML::Load(yaml), "test.yaml", "task", &h);
  return h;
}

TEST(GoalParams, ReadAxesByNameOrVectorAndGoalsAsQuaternionsOrRpy) {
  Holder h = Read("{axis: y, goals: [[2, 0, 0, 0], {rpy: [0, 0, 1.5707963267948966]}]}");
  EXPECT_EQ(h.axis.direction, Eigen::Vector3d::UnitY());
  ASSERT_EQ(h.goals.size(), 2u);
  EXPECT_NEAR(h.goals[0].q.angularDistance(Eigen::Quaterniond::Identity()), 0.0, 1e-12);
  EXPECT_NEAR((h.goals[1].q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0,
              1e-12);
  h = Read("{axis: [1, 1, 1]}");
  EXPECT_NEAR((h.axis.direction - Eigen::Vector3d(1, 1, 1) / std::sqrt(3.0)).norm(), 0.0, 1e-12);
  // It writes back what it read.
  const YAML::Node out = YamlWriteArchive::Save(h);
  EXPECT_EQ(out["axis"].size(), 3u);
  EXPECT_EQ(YamlWriteArchive::Save(Read("{axis: z}"))["axis"].as<std::string>(), "z");
}

TEST(GoalParams, RejectWhatIsNotAnAxisOrAnOrientationNamingTheKey) {
  for (const char* bad : {"{axis: w}", "{axis: [0, 0, 0]}", "{axis: [1, 2]}", "{axis: [1, a, 2]}",
                          "{goals: [[0, 0, 0, 0]]}", "{goals: [[1, 0, 0]]}",
                          "{goals: [{rpy: [1, 2]}]}", "{goals: [{ypr: [1, 2, 3]}]}",
                          "{goals: [[1, .nan, 0, 0]]}"}) {
    try {
      Read(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("test.yaml"), std::string::npos) << what;
      EXPECT_NE(what.find("task."), std::string::npos) << what;
    }
  }
}

}  // namespace
}  // namespace dmpl
