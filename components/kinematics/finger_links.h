#pragma once
// A finger's links as the hand's own geometry occupies them: each collision shape of the URDF as
// points on its surface (a box's faces, a cylinder's mantle and ends, on a grid of at most
// kLinkPointSpacingM) or, for a sphere, its centre and radius; placed in the palm frame by
// forward kinematics. What a placement must keep off the object (issue 28: a finger touching
// with its links instead of its tip). Pure: no LCM, no object model.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/hand/hand_model.h"
#include "components/kinematics/hand_kinematics.h"

namespace dmpl {

inline constexpr double kLinkPointSpacingM = 0.005;

struct LinkSolid {
  std::string link;                      // the URDF link it belongs to
  std::vector<Eigen::Vector3d> points;   // on its surface; a sphere: its centre
  double radius = 0.0;                   // 0 but for a sphere
  bool tip = false;                      // the fingertip (the finger's last link)
};

// A collision shape as a LinkSolid in its link's frame.
LinkSolid SolidOf(const CollisionShape& shape);

class FingerLinks {
 public:
  // `finger` must outlive this.
  FingerLinks(const HandModel& model, const FingerKinematics& finger);
  // The solids at joint vector `q` (this finger's), in the palm frame: base link first.
  std::vector<LinkSolid> Solids(const Eigen::VectorXd& q) const;

 private:
  const FingerKinematics& finger_;
  std::vector<int> chain_link_;    // per solid: its link's index along the chain
  std::vector<LinkSolid> local_;   // per solid: in its link's frame
};

}  // namespace dmpl
