#pragma once
// A finger's links as the hand's own geometry occupies them: each collision shape of the URDF as
// the capsule (a segment and a radius) that encloses it, placed in the palm frame by forward
// kinematics. What a placement must keep off the object (issue 28: a finger touching with its
// links instead of its tip). Pure: no LCM, no object model.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/hand/hand_model.h"
#include "components/kinematics/hand_kinematics.h"

namespace dmpl {

struct LinkCapsule {
  std::string link;                               // the URDF link it belongs to
  Eigen::Vector3d a = Eigen::Vector3d::Zero();    // its axis' ends (equal for a sphere)
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double radius = 0.0;
  bool tip = false;                               // the fingertip (the finger's last link)
};

class FingerLinks {
 public:
  // `finger` must outlive this.
  FingerLinks(const HandModel& model, const FingerKinematics& finger);
  // The capsules at joint vector `q` (this finger's), in the palm frame: base link first.
  std::vector<LinkCapsule> Capsules(const Eigen::VectorXd& q) const;

 private:
  const FingerKinematics& finger_;
  std::vector<int> chain_link_;      // per capsule: its link's index along the chain
  std::vector<LinkCapsule> local_;   // per capsule: in its link's frame
};

// The capsule that encloses a collision shape, in its link's frame: a cylinder along its axis
// with its radius; a box along its longest edge, its radius the half-diagonal of the other two;
// a sphere as a point.
LinkCapsule EnclosingCapsule(const CollisionShape& shape);

}  // namespace dmpl
