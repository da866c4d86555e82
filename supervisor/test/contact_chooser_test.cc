// The explorer's next contact on the felt surface: on a sphere felt all round the gait's point
// stays; a point beyond the finger's reach, or one where its links would lie in the felt
// surface, gives way to a candidate that is reached, clear and supported.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "components/hand/testing/project_hand.h"
#include "components/ik/finger_ik.h"
#include "supervisor/contact_chooser.h"
#include "supervisor/link_clearance.h"
#include "supervisor/test/felt_objects.h"

namespace dmpl {
namespace {

constexpr double kRadius = 0.025;
constexpr double kTipRadius = 0.012;

struct Grasp {
  ControllerView view;
  SurfaceModel surface;
};

// The nominal sphere (kRadius) felt all round (a Fibonacci lattice of contacts), held as the
// gait holds it (fig10_gait_sphere at 2 s: the tips about the palm's x axis, the thumb T below,
// the middle finger M above), each tip kTipRadius off the surface.
const Eigen::Vector3d& kCentre = testing::kGaitCentre;

Grasp SphereGrasp() {
  Grasp g;
  g.view.object.translation() = kCentre;
  for (int f = 0; f < 4; ++f) {
    const Eigen::Vector3d d = (testing::kGaitTips[f] - kCentre).normalized();
    FingerView v;
    v.tip_axis = testing::kGaitTipAxes[f].normalized();
    v.in_contact = true;
    v.force = 1.0;
    v.tip = kCentre + (kRadius + kTipRadius) * d;
    v.contact = kCentre + kRadius * d;
    g.view.fingers.push_back(v);
  }
  g.surface = testing::FeltSphere(g.view.object, kRadius, 800);
  return g;
}

ContactChooser MakeChooser(const HandModel& model) {
  ContactChoiceParams params;
  params.enabled = true;
  return ContactChooser(model, params, SupportParams{});
}

ContactRequest Request(const Grasp& g, int f, const Eigen::AngleAxisd& turn,
                       const Eigen::AngleAxisd& ride) {
  ContactRequest r;
  r.finger = f;
  r.point = kCentre + turn * (g.view.fingers[f].tip - kCentre);
  r.ride = ride;
  r.tip_radius_m = kTipRadius;
  r.min_spacing_m = 0.02;
  return r;
}

// The least clearance of finger f's links (not its tip) at `q`, from its forward kinematics.
double LinksClearance(const HandModel& model, int f, const Eigen::VectorXd& q,
                      const Grasp& g) {
  const HandKinematics kin(model);
  const FingerLinks links(model, kin.finger(f));
  double least = 1.0;
  for (const LinkSolid& solid : links.Solids(q)) {
    if (solid.tip) continue;
    if (const auto c = SurfaceClearance(solid, g.surface, g.view.object)) {
      least = std::min(least, *c);
    }
  }
  return least;
}

// The gait's point where each finger stands: kept; the finger's posture the one whose tip axis
// the controller reports; every candidate on the felt sphere; the grasp holds a load along all
// six directions.
TEST(ContactChooserTest, OnASphereFeltAllRoundEachFingersOwnPointStays) {
  const HandModel model = testing::LoadHand();
  const HandKinematics kin(model);
  const Grasp g = SphereGrasp();
  const ContactChooser chooser = MakeChooser(model);
  const Eigen::AngleAxisd none(0.0, Eigen::Vector3d::UnitX());
  for (int f = 0; f < 4; ++f) {
    SCOPED_TRACE(f);
    const ContactChoice c = chooser.Choose(Request(g, f, none, none), g.view, g.surface);
    ASSERT_EQ(c.candidates.size(), 13u);
    EXPECT_EQ(c.index, 0) << c.why;
    const ContactCandidate& own = c.chosen();
    EXPECT_TRUE(own.reached);
    // The tip a tip's radius off the sphere touches it; its links stand off it (mm).
    EXPECT_GT(own.link_clearance_m, 0.002);
    EXPECT_GT(LinksClearance(model, f, own.joints, g), 0.002);
    Eigen::Vector3d tip, axis;
    kin.finger(f).TipFrame(own.joints, &tip, &axis);
    EXPECT_LT((tip - g.view.fingers[f].tip).norm(), 1e-4);
    EXPECT_LT(std::acos(std::min(1.0, axis.dot(g.view.fingers[f].tip_axis))), 0.02);
    for (const ContactCandidate& k : c.candidates) {
      EXPECT_TRUE(k.felt);
      // The model's error on a sphere felt all round is well under a millimetre.
      EXPECT_NEAR((k.contact - kCentre).norm(), kRadius, 1e-3);
      EXPECT_NEAR((k.tip - k.contact).norm(), kTipRadius, 1e-9);
    }
    EXPECT_GT(own.support_n, 1.0);
  }
}

// The middle finger's point turned 0.6 rad about the palm's normal: under 2 cm from the fore
// finger's tip, and a candidate reached, apart and clear is taken instead.
TEST(ContactChooserTest, APointBeyondReachOrOnAnotherTipGivesWayToOneWithin) {
  const HandModel model = testing::LoadHand();
  const Grasp g = SphereGrasp();
  const ContactChooser chooser = MakeChooser(model);
  const Eigen::AngleAxisd ride(0.5, Eigen::Vector3d::UnitX());
  const ContactRequest r = Request(g, 2, Eigen::AngleAxisd(-0.6, Eigen::Vector3d::UnitX()), ride);
  const ContactChoice c = chooser.Choose(r, g.view, g.surface);
  const ContactCandidate& gait = c.candidates[0];
  EXPECT_FALSE(gait.reached && gait.spacing_m >= r.min_spacing_m);
  ASSERT_NE(c.index, 0) << c.why;
  const ContactCandidate& chosen = c.chosen();
  EXPECT_TRUE(chosen.reached);
  EXPECT_GE(chosen.spacing_m, r.min_spacing_m);
  EXPECT_GE(chosen.link_clearance_m, -0.002);
  EXPECT_GT(chosen.support_n, 1.0);
  // The nearest that does: the first ring.
  EXPECT_NEAR(chosen.offset_rad, 0.175, 1e-9);
}

// The ring finger's point turned 0.3 rad about the palm's normal, riding a half-radian turn
// after: its links would reach several millimetres into the sphere (forward kinematics of the
// IK's posture against the felt surface), and a point whose links stay out is taken instead.
TEST(ContactChooserTest, APointThatPutsALinkIntoTheFeltSurfaceGivesWayToAClearOne) {
  const HandModel model = testing::LoadHand();
  const Grasp g = SphereGrasp();
  const ContactChooser chooser = MakeChooser(model);
  const Eigen::AngleAxisd ride(0.5, Eigen::Vector3d::UnitX());
  const ContactRequest r = Request(g, 3, Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()), ride);
  const ContactChoice c = chooser.Choose(r, g.view, g.surface);
  const ContactCandidate& gait = c.candidates[0];
  EXPECT_TRUE(gait.reached);
  EXPECT_LT(gait.link_clearance_m, -0.004);
  ASSERT_NE(c.index, 0) << c.why;
  const ContactCandidate& chosen = c.chosen();
  EXPECT_TRUE(chosen.reached);
  EXPECT_GE(chosen.link_clearance_m, -0.002);
  EXPECT_GE(LinksClearance(model, 3, chosen.joints, g), -0.002);
  EXPECT_GT(chosen.support_n, 1.0);
}

// Each candidate's landing angle is its tip's axis (forward kinematics of the IK's posture)
// against the surface's normal there. With a bound below the gait's own point's angle, a
// candidate that lands nearer the tip's front is taken instead.
TEST(ContactChooserTest, APointThatLandsFarRoundTheTipGivesWayToOneNearerItsFront) {
  const HandModel model = testing::LoadHand();
  const HandKinematics kin(model);
  const Grasp g = SphereGrasp();
  const Eigen::AngleAxisd none(0.0, Eigen::Vector3d::UnitX());
  const int ring = 3;
  const ContactRequest r = Request(g, ring, none, none);
  const ContactChoice free = MakeChooser(model).Choose(r, g.view, g.surface);
  for (const ContactCandidate& c : free.candidates) {
    Eigen::Vector3d tip, axis;
    kin.finger(ring).TipFrame(c.joints, &tip, &axis);
    EXPECT_NEAR(c.contact_angle_rad, std::acos(std::clamp(-axis.dot(c.outward), -1.0, 1.0)),
                1e-9);
  }
  // At its home the ring finger touches the sphere with the side of its tip (the gait's grasp).
  const double own = free.candidates[0].contact_angle_rad;
  EXPECT_GT(own, 1.2);
  EXPECT_LT(own, 1.8);
  ContactChoiceParams params;
  params.enabled = true;
  params.max_contact_angle_rad = own - 0.05;
  const ContactChoice bounded =
      ContactChooser(model, params, SupportParams{}).Choose(r, g.view, g.surface);
  ASSERT_NE(bounded.index, 0) << bounded.why;
  EXPECT_LE(bounded.chosen().contact_angle_rad, own - 0.05);
  EXPECT_TRUE(bounded.chosen().reached);
  EXPECT_GE(bounded.chosen().link_clearance_m, -0.002);
}

// Turning the held sphere about the palm's normal carries each tip round it: half a radian
// either way every finger's links stay out of it; a whole radian one way brings the ring
// finger's links into it past half-way, and that finger is named.
TEST(ContactChooserTest, AStepStopsWhereARidingFingersLinksWouldEnterTheSurface) {
  const HandModel model = testing::LoadHand();
  const Grasp g = SphereGrasp();
  const ContactChooser chooser = MakeChooser(model);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  int blocking = -2;
  EXPECT_DOUBLE_EQ(chooser.ClearStep(x, 0.5, -1, g.view, g.surface, &blocking), 0.5);
  EXPECT_EQ(blocking, -1);
  EXPECT_DOUBLE_EQ(chooser.ClearStep(x, -0.5, -1, g.view, g.surface, &blocking), -0.5);
  EXPECT_EQ(blocking, -1);
  const double clear = chooser.ClearStep(x, 1.0, -1, g.view, g.surface, &blocking);
  EXPECT_EQ(blocking, 3);
  EXPECT_GE(clear, 0.5);
  EXPECT_LT(clear, 1.0);
  // Without the ring finger (it explores meanwhile) the whole radian is clear of the others.
  EXPECT_DOUBLE_EQ(chooser.ClearStep(x, 1.0, 3, g.view, g.surface, &blocking), 1.0);
  EXPECT_EQ(blocking, -1);
}

// The same turns finger by finger: the ring finger riding a whole radian about the palm's normal
// comes with its links into the sphere (as ClearStep found), riding half a radian it stays
// clear; and every finger riding no turn keeps its links out and its joints inside their limits.
TEST(ContactChooserTest, ARideNamesTheLinksAndJointsAFingerComesTo) {
  const HandModel model = testing::LoadHand();
  const Grasp g = SphereGrasp();
  const ContactChooser chooser = MakeChooser(model);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const RideMargins far = chooser.Ride(3, x, 1.0, g.view, g.surface);
  EXPECT_LT(far.link_clearance_m, -0.002);
  const RideMargins half = chooser.Ride(3, x, 0.5, g.view, g.surface);
  EXPECT_GE(half.link_clearance_m, -0.002);
  EXPECT_TRUE(half.reached);
  for (int f = 0; f < 4; ++f) {
    SCOPED_TRACE(f);
    const RideMargins still = chooser.Ride(f, x, 0.0, g.view, g.surface);
    EXPECT_TRUE(still.reached);
    EXPECT_GT(still.link_clearance_m, 0.0);
    EXPECT_GT(still.limit_margin_rad, 0.0);
  }
}

}  // namespace
}  // namespace dmpl
