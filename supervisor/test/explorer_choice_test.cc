#include "supervisor/explorer_choice.h"

#include "supervisor/contact_chooser.h"
#include "supervisor/supervisor_params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace dmpl {
namespace {

constexpr double kObjectRadius = 0.025;
constexpr double kTipRadius = 0.012;

// Four fingertips on a 2.5 cm sphere at the origin, their homes 90 deg apart around the palm
// normal x (the palm up: gravity along -x). Finger k stands `elevation[k]` rad above the equator
// (toward +x, away from the palm) over its home.
struct Grasp {
  explicit Grasp(const std::vector<double>& elevation) {
    view.fingers.resize(4);
    view.gravity = -Eigen::Vector3d::UnitX();
    for (int k = 0; k < 4; ++k) {
      const double a = M_PI / 2 * k;
      const Eigen::Vector3d level(0.0, std::cos(a), std::sin(a));
      home.push_back((kObjectRadius + kTipRadius) * level);
      const Eigen::Vector3d d =
          std::cos(elevation[k]) * level + std::sin(elevation[k]) * Eigen::Vector3d::UnitX();
      view.fingers[k].in_contact = true;
      view.fingers[k].force = 2.0;
      view.fingers[k].contact = kObjectRadius * d;
      view.fingers[k].tip = (kObjectRadius + kTipRadius) * d;
    }
  }
  GaitGeometry Geometry() const {
    return GaitGeometry(home, Eigen::Vector3d::Zero(), GaitSpec{}, 0.35);
  }
  std::vector<Eigen::Vector3d> home;
  ControllerView view;
};

const SupportLimits kLimits{0.5, 0.0, 2.5};

WaitRule Rule(double slack_rad, double need_n = std::numeric_limits<double>::infinity(),
              double palm_side_rad = M_PI / 2) {
  return {slack_rad, need_n, palm_side_rad, M_PI};
}
const Eigen::Vector3d kAxis = Eigen::Vector3d::UnitX();

TEST(ExplorerChoiceTest, AFingerNearlyAsFarFromHomeExploresWhenItsAbsenceLeavesMoreSupport) {
  // With one finger lifted its partner across is unopposed and pushes next to nothing: the
  // weight rests on the other pair. Fingers 1 and 3 stand 0.15 rad above the equator (their
  // pushes press the sphere toward the palm), finger 2 0.2 rad below it (its push has an upward
  // part), finger 0 on it. A 0.1 rad step about x takes finger 2 furthest from home (the reach
  // rule's choice: lifting it leaves the pair above), fingers 1 and 3 within 0.05 rad of it
  // (lifting one leaves fingers 0 and 2), finger 0 0.12 rad short.
  const Grasp grasp({0.0, 0.15, -0.2, 0.15});
  const GaitGeometry g = grasp.Geometry();
  const Eigen::AngleAxisd step(0.1, kAxis);
  ASSERT_GT(g.Deviation(2, step, grasp.view), g.Deviation(1, step, grasp.view));
  ASSERT_LT(g.Deviation(2, step, grasp.view) - g.Deviation(1, step, grasp.view), 0.05);

  const ExplorerChoice by_support =
      NextExplorer(g, kAxis, 0.1, -1, grasp.view, kLimits, Rule(0.06));
  EXPECT_EQ(by_support.furthest, 2);
  EXPECT_EQ(by_support.finger, 1);
  // Friction (0.5 of pushes of at most 2.5 N) holds what the pair above leaves; the pair of
  // fingers 0 and 2 holds more, finger 2's push carrying part of the weight.
  EXPECT_GT(by_support.support_n, by_support.furthest_support_n + 0.5);
  // While the furthest's absence leaves what the grasp needs, the reach rule stands.
  const double left = by_support.furthest_support_n;
  const auto explorer = [&](const WaitRule& rule) {
    return NextExplorer(g, kAxis, 0.1, -1, grasp.view, kLimits, rule).finger;
  };
  EXPECT_EQ(explorer(Rule(0.06, left - 0.01)), 2);
  EXPECT_EQ(explorer(Rule(0.06, left + 0.01)), 1);
  // Finger 2's contact lies 0.2 rad toward the palm, where its links near the sphere: with the
  // limit at 0.1 rad it moves whatever the others hold without it; at 0.3 rad the support rules.
  EXPECT_NEAR(PalmSideElevation(2, grasp.view), -0.2, 1e-9);
  EXPECT_EQ(explorer(Rule(0.06, left + 0.01, 0.1)), 2);
  EXPECT_EQ(explorer(Rule(0.06, left + 0.01, 0.3)), 1);

  // No slack, a slack that does not reach finger 0, or gravity not sensed: the reach rule.
  EXPECT_EQ(explorer(Rule(0.0)), 2);
  EXPECT_EQ(explorer(Rule(0.02)), 2);
  ControllerView weightless = grasp.view;
  weightless.gravity.setZero();
  EXPECT_EQ(NextExplorer(g, kAxis, 0.1, -1, weightless, kLimits, Rule(0.06)).finger, 2);
  // The finger skipped (exploring now) is never chosen: finger 3 then.
  EXPECT_EQ(NextExplorer(g, kAxis, 0.1, 1, grasp.view, kLimits, Rule(0.06)).finger, 3);
}

TEST(ExplorerChoiceTest, AFurthestFarRoundItsTipIsNotLetWait) {
  // The first test's grasp, finger 2 the furthest and finger 1 the support's choice. Finger 2's
  // tip axis is set so that its contact lies `angle` round its tip (between the tip's axis and
  // the direction from its centre to the contact): 80 deg it waits, 100 deg it explores.
  Grasp grasp({0.0, 0.15, -0.2, 0.15});
  FingerView& furthest = grasp.view.fingers[2];
  const Eigen::Vector3d into = (furthest.contact - furthest.tip).normalized();
  const Eigen::Vector3d across = into.cross(Eigen::Vector3d::UnitZ()).normalized();
  const GaitGeometry g = grasp.Geometry();
  const double left = NextExplorer(g, kAxis, 0.1, -1, grasp.view, kLimits, Rule(0.06))
                          .furthest_support_n;
  WaitRule rule = Rule(0.06, left + 0.01);
  rule.max_contact_angle_rad = M_PI / 2;
  for (const double degrees : {80.0, 100.0}) {
    const double angle = degrees * M_PI / 180.0;
    furthest.tip_axis = std::cos(angle) * into + std::sin(angle) * across;
    ASSERT_NEAR(furthest.ContactAngle(), angle, 1e-9);
    const ExplorerChoice choice = NextExplorer(g, kAxis, 0.1, -1, grasp.view, kLimits, rule);
    EXPECT_EQ(choice.furthest, 2);
    EXPECT_EQ(choice.finger, degrees < 90.0 ? 1 : 2) << degrees;
  }
}

TEST(ExplorerChoiceTest, AFingerWithoutASensedPointCountsForNoSupport) {
  // Finger 1 lost its contact a moment ago: the controller still says in contact (its debounce),
  // the sensor reports no point (zeros, 0 N). The grasp is the three others', not a fourth
  // contact at the palm's origin.
  Grasp grasp({0.0, 0.15, -0.2, 0.15});
  const Eigen::Vector3d down = grasp.view.gravity;
  const Grasp three({0.0, 0.15, -0.2, 0.15});
  grasp.view.fingers[1].contact.setZero();
  grasp.view.fingers[1].force = 0.0;
  EXPECT_FALSE(grasp.view.fingers[1].SensesPoint());
  EXPECT_EQ(GripContacts(grasp.view, -1).size(), 3u);
  EXPECT_NEAR(SupportAlong(GripContacts(grasp.view, -1), down, Eigen::Vector3d::Zero(), kLimits),
              SupportAlong(GripContacts(three.view, 1), down, Eigen::Vector3d::Zero(), kLimits),
              1e-9);
  EXPECT_EQ(PalmSideElevation(1, grasp.view), 0.0);
  // And the support rule gives no verdict on a grasp it does not know: the reach rule's finger.
  const ExplorerChoice choice =
      NextExplorer(grasp.Geometry(), kAxis, 0.1, -1, grasp.view, kLimits, Rule(0.06));
  EXPECT_EQ(choice.finger, 2);
  EXPECT_EQ(choice.finger, choice.furthest);
  EXPECT_TRUE(choice.grasp_unknown);
}

TEST(ExplorerChoiceTest, OnALevelGraspTheReachRuleStands) {
  // Every finger on the equator: each one's absence leaves the same support, so the furthest
  // (the reach rule's) explores whatever the slack.
  const Grasp grasp({0.0, 0.0, 0.0, 0.0});
  const GaitGeometry g = grasp.Geometry();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const ExplorerChoice choice = NextExplorer(g, z, 0.1, -1, grasp.view, kLimits, Rule(M_PI));
  EXPECT_EQ(choice.finger, choice.furthest);
  EXPECT_EQ(choice.finger, g.FurthestFromHome(z, 0.1, -1, grasp.view));
}

}  // namespace
}  // namespace dmpl

namespace dmpl {
namespace {

TEST(SupportLimitsTest, TheObservedFrictionIsReliedOnOnlyWhenAskedAndWithinItsBounds) {
  SupportParams p;  // friction 0.5, observed friction within [0.2, 1.0] when asked
  EXPECT_DOUBLE_EQ(p.Limits(0.8).friction, 0.5);  // not asked
  p.observed = true;
  EXPECT_DOUBLE_EQ(p.Limits(0.0).friction, 0.5);  // nothing observed yet
  EXPECT_DOUBLE_EQ(p.Limits(0.8).friction, 0.8);
  EXPECT_DOUBLE_EQ(p.Limits(3.0).friction, 1.0);
  EXPECT_DOUBLE_EQ(p.Limits(0.05).friction, 0.2);
  EXPECT_DOUBLE_EQ(p.Limits(0.8).max_push_n, p.max_push_n);
}

TEST(SupportLimitsTest, AGraspOnAGrippyObjectHoldsMoreWithoutAFinger) {
  // Fingers 1 and 3 above the equator press the sphere toward the palm: with finger 0 lifted,
  // finger 2 alone pushes up, and friction carries the rest.
  const Grasp grasp({0.0, 0.15, -0.2, 0.15});
  SupportParams p;
  p.observed = true;
  const double slick = SupportWithout(grasp.view, 0, p.Limits(0.3));
  const double grippy = SupportWithout(grasp.view, 0, p.Limits(0.9));
  EXPECT_GT(grippy, slick + 0.5);
}

}  // namespace
}  // namespace dmpl
