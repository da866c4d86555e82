// What touch tells of the surface (components/controller/contact_sensing.h) against the
// simulator's truth: the normal from the tip geometry and the sensed joints against Bullet's
// contact normal, no link contact found while only the tips touch, and one found (and in the
// simulator's truth) when a finger flexes its middle link into the object.
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

// The object (GetParam()'s shape) held by the static grasp squeezed, released and left to settle
// in the four tips.
void SqueezeAndSettle(HandSim* hand) {
  std::string why;
  ASSERT_TRUE(hand->SetJointTargets(testing::SqueezeTargets(), &why)) << why;
  for (int i = 0; i < 300; ++i) hand->Step();
  hand->ReleaseObject();
  for (int i = 0; i < 1000; ++i) hand->Step();
}

TEST_P(ContactSensingSimTest, NormalFromTheTipMatchesTheSimulatorsAndNoLinkTouches) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  ObjectParams object;
  object.shape = GetParam();
  object.position = {0.09, 0.0, 0.02};
  HandSim hand(model, testing::StaticGraspSim(), object);
  ASSERT_NO_FATAL_FAILURE(SqueezeAndSettle(&hand));
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
    EXPECT_EQ(tip.link_force, 0.0) << kin.finger(f).name() << ": the simulator's truth";
    // The check can tell: the tip force taken the wrong way round leaves twice J^T f.
    EXPECT_NE(FindLinkContact(kin, f, joints.position, joints.effort, tip.force,
                              -n.normal, 0.1)
                  .joint,
              -1)
        << kin.finger(f).name();
  }
}

// The friction the joints feel: with each tip's sensed normal force and the tangential force
// its efforts imply (TipTangentialForce), the forces the fingertips take from a held object add
// up to its weight, which the normal forces alone do not.
TEST_P(ContactSensingSimTest, TheTipsForcesWithTheirFrictionCarryTheWeight) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  ObjectParams object;
  object.shape = GetParam();
  object.position = {0.09, 0.0, 0.02};
  object.mass = 0.1;
  HandSim hand(model, testing::StaticGraspSim(), object);
  ASSERT_NO_FATAL_FAILURE(SqueezeAndSettle(&hand));
  const JointState joints = hand.joints();
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d tangential_sum = Eigen::Vector3d::Zero();
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const TipState& tip = hand.tactile()[f];
    ASSERT_TRUE(tip.in_contact) << kin.finger(f).name();
    const Eigen::Vector3d n =
        NormalFromTip(kin.TipPosition(f, joints.position), tip.position, 0.0).normal;
    const Eigen::Vector3d t =
        TipTangentialForce(kin, f, joints.position, joints.effort, tip.force, tip.position,
                           hand.gravity_in_palm());
    EXPECT_LT(std::abs(t.dot(n)), 1e-9) << kin.finger(f).name();
    normal_sum += tip.force * n;
    tangential_sum += t;
  }
  const Eigen::Vector3d weight = object.mass * hand.gravity_in_palm();
  const Eigen::Vector3d total = normal_sum + tangential_sum;
  std::printf("weight %.3f N; normal forces add up to %.3f N off it, with friction %.3f N off\n",
              weight.norm(), (normal_sum - weight).norm(), (total - weight).norm());
  // At rest the tips' forces on the object balance its weight (measured: within 6 mN of its
  // 0.98 N, the normal forces alone 1.3 N off); 50 mN leaves room for Bullet's contact points,
  // spread over the tip's sub-millimetre penetration.
  EXPECT_LT((total - weight).norm(), 0.05);
  EXPECT_GT((normal_sum - weight).norm(), 0.5 * weight.norm()) << "a test that cannot fail";
}

// A held sphere beside the forefinger's middle link, the finger flexing into it: the simulator's
// truth names a force on the finger's links (no tip touches), and the joints' efforts find it.
TEST(LinkContactSimTest, AFingerFlexedIntoAnObjectTouchesWithItsLink) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  const int f = kin.FindFinger("F");
  const std::vector<int>& joints = kin.joint_indices(f);
  // Every joint as near straight as its limits allow; the forefinger's proximal joint flexed
  // a little.
  std::vector<double> q(model.num_actuated(), 0.0);
  for (int k = 0; k < kin.num_fingers(); ++k) {
    for (int j = 0; j < kin.finger(k).num_joints(); ++j) {
      q[kin.joint_indices(k)[j]] =
          std::clamp(0.0, kin.finger(k).lower()[j], kin.finger(k).upper()[j]);
    }
  }
  q[joints[1]] = 0.2;
  Eigen::Vector3d axis;
  Eigen::Matrix3Xd omega;
  kin.finger(f).TipAxis(kin.FingerJoints(f, q), &axis, &omega);
  // The middle of the middle link (3.84 cm), 2.67 cm + 1.92 cm behind the tip centre; the
  // sphere (1.5 cm) 2 mm beyond the link's side (0.9 cm), the way the finger flexes.
  const Eigen::Vector3d middle = kin.TipPosition(f, q) - (0.0267 + 0.0192) * axis;
  const Eigen::Vector3d flexes = omega.col(1).normalized().cross(axis);
  ObjectParams object;
  object.radius = 0.015;
  const Eigen::Vector3d centre = middle + (0.009 + 0.015 + 0.002) * flexes;
  object.position = {centre.x(), centre.y(), centre.z()};
  HandSim hand(model, testing::StaticGraspSim(), object);
  hand.SetJointPositions(q);
  std::vector<double> target = q;
  target[joints[2]] = 0.4;  // the middle link swings into the sphere
  std::string why;
  ASSERT_TRUE(hand.SetJointTargets(target, &why)) << why;
  for (int i = 0; i < 500; ++i) hand.Step();
  const TipState& tip = hand.tactile()[f];
  EXPECT_FALSE(tip.in_contact);
  EXPECT_GT(tip.link_force, 0.1);
  for (int k = 0; k < kin.num_fingers(); ++k) {
    if (k == f) continue;
    EXPECT_EQ(hand.tactile()[k].link_force, 0.0) << kin.finger(k).name();
  }
  const JointState state = hand.joints();
  const LinkContact link = FindLinkContact(kin, f, state.position, state.effort, 0.0,
                                           Eigen::Vector3d::Zero(), 0.1);
  EXPECT_EQ(link.joint, 2) << link.link << " " << link.torque_nm << " N m";
}

INSTANTIATE_TEST_SUITE_P(Shapes, ContactSensingSimTest, ::testing::Values("sphere", "ellipsoid"));

}  // namespace
}  // namespace dmpl
