#include "components/controller/contact_sensing.h"

#include <gtest/gtest.h>

#include "components/hand/testing/project_hand.h"

namespace dmpl {
namespace {

TEST(ContactSensingTest, TheNormalRunsFromTheContactToTheTipCentre) {
  const Eigen::Vector3d centre(0.05, 0.01, 0.1);
  const Eigen::Vector3d out = Eigen::Vector3d(1, -2, 0.5).normalized();
  const ContactNormal n = NormalFromTip(centre, centre - 0.012 * out, 0.012);
  EXPECT_TRUE(n.normal.isApprox(out, 1e-12));
  EXPECT_NEAR(n.off_surface_m, 0.0, 1e-12);
  // A sensed point 1 mm inside the tip sphere: the same direction, said to be 1 mm off.
  EXPECT_NEAR(NormalFromTip(centre, centre - 0.011 * out, 0.012).off_surface_m, -0.001, 1e-12);
}

class LinkContactTest : public ::testing::Test {
 protected:
  LinkContactTest() : model_(testing::LoadHand()), kin_(model_) {
    q_.assign(kin_.num_joints(), 0.0);
    for (int j : kin_.joint_indices(kF)) q_[j] = 0.5;
    q_[kin_.joint_indices(kF)[0]] = 0.0;
  }
  // The efforts that hold a tip force of `force` N along `normal` (into the fingertip), plus
  // `extra` on the finger's joints (a contact elsewhere).
  std::vector<double> Holding(double force, const Eigen::Vector3d& normal,
                              const Eigen::Vector4d& extra) const {
    Eigen::Matrix3Xd jac;
    kin_.finger(kF).PositionJacobian(kin_.FingerJoints(kF, q_), &jac);
    const Eigen::VectorXd tau = -jac.transpose() * (force * normal);
    std::vector<double> effort(kin_.num_joints(), 0.0);
    for (int j = 0; j < 4; ++j) effort[kin_.joint_indices(kF)[j]] = tau[j] + extra[j];
    return effort;
  }
  static constexpr int kF = 1;  // the forefinger
  HandModel model_;
  HandKinematics kin_;
  std::vector<double> q_;
};

TEST_F(LinkContactTest, ATipContactIsNotMistakenForALinkContact) {
  const Eigen::Vector3d normal = Eigen::Vector3d(-1, 0, -0.3).normalized();
  const std::vector<double> effort = Holding(2.0, normal, Eigen::Vector4d::Zero());
  EXPECT_EQ(FindLinkContact(kin_, kF, q_, effort, 2.0, normal, 0.1).joint, -1);
}

TEST_F(LinkContactTest, FrictionAtTheTipIsNotMistakenForALinkContact) {
  // A grip carrying weight: 2 N along the normal and 1.6 N across it (friction 0.8). The
  // tangential part alone leaves more than 0.1 N m on the proximal joints.
  const Eigen::Vector3d normal = Eigen::Vector3d(-1, 0, -0.3).normalized();
  const Eigen::Vector3d across = normal.unitOrthogonal();
  const Eigen::Vector3d total = 2.0 * normal + 1.6 * across;
  const std::vector<double> effort = Holding(total.norm(), total.normalized(),
                                             Eigen::Vector4d::Zero());
  ASSERT_GE(FindLinkContact(kin_, kF, q_, effort, 2.0, normal, 0.1).joint, 0)
      << "without friction the tangential force reads as a link contact";
  EXPECT_EQ(FindLinkContact(kin_, kF, q_, effort, 2.0, normal, 0.1, 1.0).joint, -1);
  // Beyond the friction allowed (0.1: at most 0.2 N of the 1.6 N across) it is not explained.
  EXPECT_GE(FindLinkContact(kin_, kF, q_, effort, 2.0, normal, 0.1, 0.1).joint, 0);
}

TEST_F(LinkContactTest, ALinkContactIsFoundAndNamed) {
  const Eigen::Vector3d normal = Eigen::Vector3d(-1, 0, -0.3).normalized();
  // 0.3 N m on the abduction and the first flexion joint: a push on the proximal link.
  const std::vector<double> effort = Holding(1.0, normal, Eigen::Vector4d(0.1, 0.3, 0, 0));
  const LinkContact c = FindLinkContact(kin_, kF, q_, effort, 1.0, normal, 0.1);
  EXPECT_EQ(c.joint, 1);
  // Friction at the tip (up to 1.5 N across) does not explain it away.
  EXPECT_EQ(FindLinkContact(kin_, kF, q_, effort, 1.0, normal, 0.1, 1.5).joint, 1);
  EXPECT_NEAR(c.torque_nm, 0.3, 1e-9);
  const int joint = model_.fingers()[kF].joints[1];
  EXPECT_EQ(c.link, model_.links()[model_.actuated_joint(joint).child_link].name);
  // With no tip contact at all (the tip reads 0 N) the same push is found too.
  const std::vector<double> alone = Holding(0.0, normal, Eigen::Vector4d(0.1, 0.3, 0.2, 0));
  EXPECT_EQ(FindLinkContact(kin_, kF, q_, alone, 0.0, normal, 0.1).joint, 2);
}

}  // namespace
}  // namespace dmpl
