// A finger placed again in a recovery: over its point as planned, or, with
// supervisor.replace_on_felt_surface, over a point of the felt surface where the hand model finds
// its links clear.
#include <gtest/gtest.h>

#include <cmath>

#include "components/hand/testing/project_hand.h"
#include "supervisor/finger_replacer.h"

namespace dmpl {
namespace {

constexpr double kRadius = 0.025;
constexpr double kTipRadius = 0.012;
constexpr int kRing = 3;

// The nominal sphere felt all round (a Fibonacci lattice of contacts), held as the gait holds it
// (fig10_gait_sphere at 2 s), the ring finger R's contact lost; its home (where it stood when the
// tasks began) lies `home_turn` rad about the palm's normal from where it stood.
Blackboard SphereHeldWithoutR(double home_turn) {
  const Eigen::Vector3d centre(0.071, 0.002, 0.018);
  const Eigen::Vector3d tips[] = {{0.0715, 0.0163, -0.0162}, {0.0705, 0.0376, 0.0323},
                                  {0.0698, 0.0041, 0.0554}, {0.0708, -0.0336, 0.0194}};
  const Eigen::Vector3d axes[] = {{0.024, -0.730, 0.683}, {0.319, -0.122, -0.940},
                                  {0.643, 0.038, -0.765}, {0.148, 0.110, -0.983}};
  Blackboard board({"T", "F", "M", "R"});
  board.view.object.translation() = centre;
  board.home_centre = centre;
  board.tip_radius_m = kTipRadius;
  board.view.fingers.resize(4);
  board.home.resize(4);
  for (int f = 0; f < 4; ++f) {
    const Eigen::Vector3d d = (tips[f] - centre).normalized();
    FingerView& v = board.view.fingers[f];
    v.tip_axis = axes[f].normalized();
    v.in_contact = f != kRing;
    v.force = v.in_contact ? 1.0 : 0.0;
    v.tip = centre + (kRadius + kTipRadius) * d;
    v.contact = v.in_contact ? Eigen::Vector3d(centre + kRadius * d) : Eigen::Vector3d::Zero();
    board.home[f] = v.tip;
  }
  board.home[kRing] = centre + Eigen::AngleAxisd(home_turn, Eigen::Vector3d::UnitX()) *
                                   (board.home[kRing] - centre);
  const int n = 800;
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    const double phi = i * M_PI * (3.0 - std::sqrt(5.0));
    const Eigen::Vector3d d(r * std::cos(phi), r * std::sin(phi), z);
    board.surface.Add(board.view.object, centre + kRadius * d, d, 0.001 * i);
  }
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

ContactChooser MakeChooser(const HandModel& model) {
  ContactChoiceParams choice;
  choice.enabled = true;
  return ContactChooser(model, choice, SupportLimits{0.5, 0.0, 2.5});
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
  const Eigen::Vector3d over_home = PointOver(&plain, &as_planned);
  EXPECT_LT((over_home - (home + params.replace_lift_m * (home - centre).normalized())).norm(),
            1e-9);
}

// Its home where it stood: the chooser keeps it, and the target is the one of before.
TEST(FingerReplacerTest, AFingerWhoseHomeIsClearGoesOverItsHome) {
  const HandModel model = testing::LoadHand();
  const ContactChooser chooser = MakeChooser(model);
  SupervisorParams params;
  params.replace_on_felt_surface = true;
  Blackboard board = SphereHeldWithoutR(0.0);
  const Eigen::Vector3d centre = board.view.object.translation();
  const Eigen::Vector3d home = board.home[kRing];
  FingerReplacer replacer(&board, params, &chooser, 0.026);
  const Eigen::Vector3d over = PointOver(&board, &replacer);
  EXPECT_LT((over - (home + params.replace_lift_m * (home - centre).normalized())).norm(), 1e-9);
  EXPECT_EQ(board.note.find("placing finger R again at"), std::string::npos) << board.note;
}

}  // namespace
}  // namespace dmpl
