// A finger's links as capsules: each encloses its collision shape, follows its joints, and the
// last is the fingertip where forward kinematics puts it.
#include <gtest/gtest.h>

#include <random>

#include "components/hand/testing/project_hand.h"
#include "components/kinematics/finger_links.h"

namespace dmpl {
namespace {

using testing::LoadHand;

double DistanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0)
                                        : 0.0;
  return (p - (a + t * ab)).norm();
}

Eigen::Isometry3d SomeOrigin() {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  origin.translation() = Eigen::Vector3d(0.01, -0.02, 0.005);
  return origin;
}

TEST(EnclosingCapsuleTest, ABoxsCornersLieOnOrInsideItsCapsule) {
  CollisionShape box;
  box.kind = CollisionShape::Kind::kBox;
  box.box_size = Eigen::Vector3d(0.012, 0.04, 0.009);  // longest along y
  box.origin = SomeOrigin();
  const LinkCapsule c = EnclosingCapsule(box);
  EXPECT_NEAR((c.b - c.a).norm(), 0.04, 1e-12);
  EXPECT_NEAR(c.radius, 0.5 * std::hypot(0.012, 0.009), 1e-12);
  double worst = -1.0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1 ? 0.5 : -0.5) * 0.012, (i & 2 ? 0.5 : -0.5) * 0.04,
                                 (i & 4 ? 0.5 : -0.5) * 0.009);
    worst = std::max(worst, DistanceToSegment(box.origin * corner, c.a, c.b) - c.radius);
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(worst, -1e-12) << "the corners touch it: the tightest capsule along that edge";
}

TEST(EnclosingCapsuleTest, ACylinderRunsAlongItsAxisAndASphereIsAPoint) {
  CollisionShape cylinder;
  cylinder.kind = CollisionShape::Kind::kCylinder;
  cylinder.radius = 0.008;
  cylinder.length = 0.03;
  cylinder.origin = SomeOrigin();
  const LinkCapsule c = EnclosingCapsule(cylinder);
  EXPECT_TRUE(c.a.isApprox(cylinder.origin * Eigen::Vector3d(0, 0, -0.015), 1e-12));
  EXPECT_TRUE(c.b.isApprox(cylinder.origin * Eigen::Vector3d(0, 0, 0.015), 1e-12));
  EXPECT_EQ(c.radius, 0.008);
  CollisionShape sphere;
  sphere.kind = CollisionShape::Kind::kSphere;
  sphere.radius = 0.01;
  sphere.origin = SomeOrigin();
  const LinkCapsule s = EnclosingCapsule(sphere);
  EXPECT_EQ(s.a, s.b);
  EXPECT_TRUE(s.a.isApprox(sphere.origin.translation(), 1e-15));
  EXPECT_EQ(s.radius, 0.01);
}

// The last capsule is the fingertip sphere where the tip's forward kinematics is; turning joint
// j moves the capsules of the links it carries and no other.
TEST(FingerLinksTest, CapsulesFollowTheirJointsAndEndAtTheTip) {
  const HandModel model = LoadHand();
  const HandKinematics kin(model);
  std::mt19937 rng(5);
  for (int f = 0; f < kin.num_fingers(); ++f) {
    const FingerKinematics& finger = kin.finger(f);
    const FingerLinks links(model, finger);
    Eigen::VectorXd q(finger.num_joints());
    for (int k = 0; k < q.size(); ++k) {
      q[k] = std::uniform_real_distribution<double>(finger.lower()[k], finger.upper()[k])(rng);
    }
    const std::vector<LinkCapsule> at_q = links.Capsules(q);
    ASSERT_FALSE(at_q.empty());
    const LinkCapsule& tip = at_q.back();
    EXPECT_TRUE(tip.tip);
    EXPECT_LT((tip.a - finger.TipPosition(q)).norm(), 1e-12) << finger.name();
    EXPECT_NEAR(tip.radius, model.tip_radius(), 1e-12) << finger.name();
    for (int j = 0; j < finger.num_joints(); ++j) {
      Eigen::VectorXd turned = q;
      turned[j] += 0.1;
      const std::vector<LinkCapsule> after = links.Capsules(turned);
      bool carried = false;  // from the link joint j moves on, every link rides on it
      for (size_t i = 0; i < at_q.size(); ++i) {
        carried = carried || at_q[i].link == finger.LinkAfterJoint(j);
        if (carried) continue;
        EXPECT_EQ(after[i].a, at_q[i].a) << finger.name() << " joint " << j << " moved "
                                         << at_q[i].link;
        EXPECT_EQ(after[i].b, at_q[i].b) << finger.name() << " joint " << j;
      }
      EXPECT_TRUE(carried) << finger.name() << ": no capsule on " << finger.LinkAfterJoint(j);
      EXPECT_GT((after.back().a - tip.a).norm(), 1e-3) << finger.name() << " joint " << j;
    }
  }
}

}  // namespace
}  // namespace dmpl
