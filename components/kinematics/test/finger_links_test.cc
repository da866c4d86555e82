// A finger's links as solids: points on each collision shape's surface (a sphere: its centre
// and radius), following their joints, the last the fingertip where forward kinematics puts it.
#include <gtest/gtest.h>

#include <random>

#include "components/hand/testing/project_hand.h"
#include "components/kinematics/finger_links.h"

namespace dmpl {
namespace {

using testing::LoadHand;

Eigen::Isometry3d SomeOrigin() {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  origin.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  origin.translation() = Eigen::Vector3d(0.01, -0.02, 0.005);
  return origin;
}

// Every point lies on one of the box's faces; its corners are among them; no point is farther
// than the spacing from another (no face left bare).
TEST(LinkSolidTest, ABoxIsPointsOnItsFacesNoFurtherApartThanTheSpacing) {
  CollisionShape box;
  box.kind = CollisionShape::Kind::kBox;
  box.box_size = Eigen::Vector3d(0.0275, 0.0196, 0.054);  // a finger's middle link
  box.origin = SomeOrigin();
  const LinkSolid s = SolidOf(box);
  EXPECT_EQ(s.radius, 0.0);
  const Eigen::Vector3d half = box.box_size / 2;
  int corners = 0;
  for (const Eigen::Vector3d& p : s.points) {
    const Eigen::Vector3d local = box.origin.inverse() * p;
    const Eigen::Vector3d ratio = local.cwiseAbs().cwiseQuotient(half);
    EXPECT_LT(ratio.maxCoeff(), 1 + 1e-9);
    EXPECT_GT(ratio.maxCoeff(), 1 - 1e-9) << "a point inside the box";
    corners += (ratio.array() > 1 - 1e-9).all();
    double nearest = 1.0;
    for (const Eigen::Vector3d& q : s.points) {
      if (&q != &p) nearest = std::min(nearest, (q - p).norm());
    }
    EXPECT_LE(nearest, kLinkPointSpacingM + 1e-12);
  }
  EXPECT_EQ(corners, 8);
}

TEST(LinkSolidTest, ACylindersPointsLieOnItsMantleOrEndsAndASphereIsItsCentre) {
  CollisionShape cylinder;
  cylinder.kind = CollisionShape::Kind::kCylinder;
  cylinder.radius = 0.008;
  cylinder.length = 0.03;
  cylinder.origin = SomeOrigin();
  const LinkSolid c = SolidOf(cylinder);
  ASSERT_GT(c.points.size(), 16u);
  for (const Eigen::Vector3d& p : c.points) {
    const Eigen::Vector3d local = cylinder.origin.inverse() * p;
    const double r = std::hypot(local.x(), local.y());
    const bool mantle = std::abs(r - 0.008) < 1e-9 && std::abs(local.z()) < 0.015 + 1e-9;
    const bool end = std::abs(std::abs(local.z()) - 0.015) < 1e-9 && r < 0.008 + 1e-9;
    EXPECT_TRUE(mantle || end) << local.transpose();
  }
  CollisionShape sphere;
  sphere.kind = CollisionShape::Kind::kSphere;
  sphere.radius = 0.01;
  sphere.origin = SomeOrigin();
  const LinkSolid s = SolidOf(sphere);
  ASSERT_EQ(s.points.size(), 1u);
  EXPECT_TRUE(s.points[0].isApprox(sphere.origin.translation(), 1e-15));
  EXPECT_EQ(s.radius, 0.01);
}

// The last solid is the fingertip sphere where the tip's forward kinematics is; turning joint
// j moves the solids of the links it carries and no other.
TEST(FingerLinksTest, SolidsFollowTheirJointsAndEndAtTheTip) {
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
    const std::vector<LinkSolid> at_q = links.Solids(q);
    ASSERT_FALSE(at_q.empty());
    const LinkSolid& tip = at_q.back();
    EXPECT_TRUE(tip.tip);
    ASSERT_EQ(tip.points.size(), 1u);
    EXPECT_LT((tip.points[0] - finger.TipPosition(q)).norm(), 1e-12) << finger.name();
    EXPECT_NEAR(tip.radius, model.tip_radius(), 1e-12) << finger.name();
    for (int j = 0; j < finger.num_joints(); ++j) {
      Eigen::VectorXd turned = q;
      turned[j] += 0.1;
      const std::vector<LinkSolid> after = links.Solids(turned);
      bool carried = false;  // from the link joint j moves on, every link rides on it
      for (size_t i = 0; i < at_q.size(); ++i) {
        carried = carried || at_q[i].link == finger.LinkAfterJoint(j);
        if (!carried) {
          EXPECT_EQ(after[i].points, at_q[i].points) << finger.name() << " joint " << j
                                                     << " moved " << at_q[i].link;
        }
      }
      EXPECT_TRUE(carried) << finger.name() << ": no solid on " << finger.LinkAfterJoint(j);
      EXPECT_GT((after.back().points[0] - tip.points[0]).norm(), 1e-3)
          << finger.name() << " joint " << j;
    }
  }
}

}  // namespace
}  // namespace dmpl
