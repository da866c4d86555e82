// What touch tells of the surface (components/controller/contact_sensing.h) against the
// simulator's truth: the normal from the tip geometry and the sensed joints against Bullet's
// contact normal, and no link contact found while only the tips touch.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "components/controller/contact_sensing.h"
#include "components/hand/testing/project_hand.h"
#include "sim_process/sim/hand_sim.h"
#include "sim_process/sim/testing/static_grasp.h"

namespace dmpl {
namespace {

using testing::LoadHand;

class ContactSensingSimTest : public ::testing::TestWithParam<const char*> {};

TEST_P(ContactSensingSimTest, NormalFromTheTipMatchesTheSimulatorsAndNoLinkTouches) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  ObjectParams object;
  object.shape = GetParam();
  object.position = {0.09, 0.0, 0.02};
  HandSim hand(model, testing::StaticGraspSim(), object);
  std::string why;
  ASSERT_TRUE(hand.SetJointTargets(testing::SqueezeTargets(), &why)) << why;
  for (int i = 0; i < 300; ++i) hand.Step();
  hand.ReleaseObject();
  for (int i = 0; i < 1000; ++i) hand.Step();
  const JointState joints = hand.joints();
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const TipState& tip = hand.tactile()[f];
    ASSERT_TRUE(tip.in_contact) << kin.finger(f).name();
    const ContactNormal n =
        NormalFromTip(kin.TipPosition(f, joints.position), tip.position, model.tip_radius());
    const double angle = std::acos(std::clamp(n.normal.dot(tip.normal), -1.0, 1.0));
    std::printf("%s on the %s: normal %.2f deg from Bullet's, point %.2f mm off the tip, %.2f N\n",
                kin.finger(f).name().c_str(), GetParam(), angle * 180 / M_PI,
                n.off_surface_m * 1e3, tip.force);
    // Bullet's point is the force-weighted mean of its contact points on the tip sphere, whose
    // penetration is a fraction of a millimetre: the two normals agree within a degree or two.
    EXPECT_LT(angle, 2.0 * M_PI / 180) << kin.finger(f).name();
    EXPECT_LT(std::abs(n.off_surface_m), 1e-3) << kin.finger(f).name();
    const LinkContact link = FindLinkContact(kin, f, joints.position, joints.effort,
                                             tip.force, n.normal, 0.1);
    EXPECT_EQ(link.joint, -1) << kin.finger(f).name() << ": " << link.link << " "
                              << link.torque_nm << " N m";
    // The check can tell: the tip force taken the wrong way round leaves twice J^T f.
    EXPECT_NE(FindLinkContact(kin, f, joints.position, joints.effort, tip.force,
                              -n.normal, 0.1)
                  .joint,
              -1)
        << kin.finger(f).name();
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, ContactSensingSimTest, ::testing::Values("sphere", "ellipsoid"));

}  // namespace
}  // namespace dmpl
