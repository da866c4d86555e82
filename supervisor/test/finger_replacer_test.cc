// A finger placed again in a recovery: over its point as planned, or, with
// supervisor.replace_on_felt_surface, over a point of the felt surface where the hand model finds
// its links clear.
#include <gtest/gtest.h>

#include <cmath>

#include "components/hand/testing/project_hand.h"
#include "supervisor/finger_replacer.h"
#include "supervisor/test/felt_objects.h"

namespace dmpl {
namespace {

constexpr double kRadius = 0.025;
constexpr double kTipRadius = 0.012;
constexpr int kRing = 3;

// The nominal sphere felt all round (a Fibonacci lattice of contacts), held as the gait holds it
// (fig10_gait_sphere at 2 s), the ring finger R's contact lost; its home (where it stood when the
// tasks began) lies `home_turn` rad about the palm's normal from where it stood.
Blackboard SphereHeldWithoutR(double home_turn) {
  const Eigen::Vector3d& centre = testing::kGaitCentre;
  Blackboard board({"T", "F", "M", "R"});
  board.view.object.translation() = centre;
  board.home_centre = centre;
  board.tip_radius_m = kTipRadius;
  board.view.fingers.resize(4);
  board.home.resize(4);
  for (int f = 0; f < 4; ++f) {
    const Eigen::Vector3d d = (testing::kGaitTips[f] - centre).normalized();
    FingerView& v = board.view.fingers[f];
    v.tip_axis = testing::kGaitTipAxes[f].normalized();
    v.in_contact = f != kRing;
    v.force = v.in_contact ? 1.0 : 0.0;
    v.tip = centre + (kRadius + kTipRadius) * d;
    v.contact = v.in_contact ? Eigen::Vector3d(centre + kRadius * d) : Eigen::Vector3d::Zero();
    board.home[f] = v.tip;
  }
  board.home[kRing] = centre + Eigen::AngleAxisd(home_turn, Eigen::Vector3d::UnitX()) *
                                   (board.home[kRing] - centre);
  board.surface = testing::FeltSphere(board.view.object, kRadius, 800);
  return board;
}

// Ticks the recovery until R is moved over its point; returns that target.
Eigen::Vector3d PointOver(Blackboard* board, FingerReplacer* replacer) {
  board->now = 0.3;  // past replace_after_s since the recovery began (at 0)
  replacer->Tick(0.0);
  EXPECT_EQ(board->out.task.fingers[kRing].primitive, Primitive::kPosition) << "lifted";
  board->reached[kRing] = true;
  board->now += 0.01;
  replacer->Tick(0.0);
  return board->out.task.fingers[kRing].target;
}

// Over R's home by the lift, out from the centre: where a finger placed as planned goes.
Eigen::Vector3d OverHome(const Blackboard& board, double lift) {
  const Eigen::Vector3d& home = board.home[kRing];
  return home + lift * (home - board.view.object.translation()).normalized();
}

ContactChooser MakeChooser(const HandModel& model) {
  ContactChoiceParams choice;
  choice.enabled = true;
  return ContactChooser(model, choice, SupportParams{});
}

// R's home 0.9 rad about the palm's normal from where it stood: over it the hand model puts its
// links more than 2 mm into the felt sphere. Placed on the felt surface, it goes over a
// point of the sphere where they stay clear (asked again there, the chooser keeps it), a tip's
// radius and the lift off the surface; without the option, over its home.
TEST(FingerReplacerTest, AFingerPlacedOnTheFeltSurfaceGoesWhereItsLinksStayClear) {
  const HandModel model = testing::LoadHand();
  const ContactChooser chooser = MakeChooser(model);
  SupervisorParams params;
  params.replace_on_felt_surface = true;
  Blackboard board = SphereHeldWithoutR(0.9);
  const Eigen::Vector3d centre = board.view.object.translation();
  const Eigen::Vector3d home = board.home[kRing];
  ContactRequest asked;
  asked.finger = kRing;
  asked.point = home;
  asked.tip_radius_m = kTipRadius;
  asked.min_spacing_m = 0.026;
  const ContactChoice there = chooser.Choose(asked, board.view, board.surface);
  ASSERT_LT(there.candidates[0].link_clearance_m, -0.002) << "the home point is not clear";

  FingerReplacer replacer(&board, params, &chooser, 0.026);
  const Eigen::Vector3d over = PointOver(&board, &replacer);
  EXPECT_GT((over - home).norm(), 0.005) << "moved off its home point";
  const double out = (over - centre).norm();
  EXPECT_NEAR(out, kRadius + kTipRadius + params.replace_lift_m, 1e-3);
  EXPECT_NE(board.note.find("placing finger R again at"), std::string::npos) << board.note;
  asked.point = centre + (over - centre) * (kRadius + kTipRadius) / out;
  const ContactChoice again = chooser.Choose(asked, board.view, board.surface);
  EXPECT_EQ(again.index, 0) << again.why;
  EXPECT_TRUE(again.chosen().reached);
  EXPECT_GE(again.chosen().link_clearance_m, -0.002);

  SupervisorParams off;
  Blackboard plain = SphereHeldWithoutR(0.9);
  FingerReplacer as_planned(&plain, off, &chooser, 0.026);
  EXPECT_LT((PointOver(&plain, &as_planned) - OverHome(plain, params.replace_lift_m)).norm(),
            1e-9);
}

// Its home where it stood: the chooser keeps it, and the target is the one of before.
TEST(FingerReplacerTest, AFingerWhoseHomeIsClearGoesOverItsHome) {
  const HandModel model = testing::LoadHand();
  const ContactChooser chooser = MakeChooser(model);
  SupervisorParams params;
  params.replace_on_felt_surface = true;
  Blackboard board = SphereHeldWithoutR(0.0);
  FingerReplacer replacer(&board, params, &chooser, 0.026);
  EXPECT_LT((PointOver(&board, &replacer) - OverHome(board, params.replace_lift_m)).norm(), 1e-9);
  EXPECT_EQ(board.note.find("placing finger R again at"), std::string::npos) << board.note;
}

}  // namespace
}  // namespace dmpl
