#pragma once
// The hand as described by its URDF (parsed with urdfdom), in a form both the simulator and the
// kinematics use: links in depth-first order (parents before children), the joints that connect
// them, the actuated joints in finger order, and the fingers' chains.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/hand/hand_params.h"

namespace dmpl {

struct CollisionShape {
  enum class Kind { kBox, kSphere, kCylinder };
  Kind kind = Kind::kBox;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // in the link frame
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();
  double radius = 0.0;
  double length = 0.0;  // cylinder, along z
};

struct LinkInfo {
  std::string name;
  int parent_link = -1;   // -1 for the root (the palm)
  int parent_joint = -1;  // index into HandModel::joints(), -1 for the root
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();          // in the link frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();      // about the com, link-frame axes
  std::vector<CollisionShape> collisions;
};

struct JointInfo {
  enum class Type { kRevolute, kFixed };
  std::string name;
  Type type = Type::kFixed;
  int parent_link = -1;
  int child_link = -1;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // child frame at q = 0, in parent
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();           // unit, in the child frame
  double lower = 0.0, upper = 0.0;                           // rad (continuous: +-inf)
  double effort = 0.0, velocity = 0.0;
  int actuated_index = -1;                                   // into the joint vector, or -1
};

struct FingerInfo {
  std::string name;
  int tip_link = -1;
  std::vector<int> links;   // root's child ... tip (link indices)
  std::vector<int> joints;  // actuated indices of this finger's joints, base first
};

class HandModel {
 public:
  // Parses and validates; any problem is a ConfigError naming the file and what is wrong.
  static HandModel Load(const HandParams& params);

  const std::string& urdf_path() const { return urdf_path_; }
  const std::vector<LinkInfo>& links() const { return links_; }
  const std::vector<JointInfo>& joints() const { return joints_; }
  const std::vector<FingerInfo>& fingers() const { return fingers_; }
  // Actuated joints in the order of the joint vector (finger by finger, base to tip).
  const std::vector<int>& actuated() const { return actuated_; }
  int num_actuated() const { return static_cast<int>(actuated_.size()); }
  const JointInfo& actuated_joint(int i) const { return joints_[actuated_[i]]; }
  std::vector<std::string> actuated_names() const;
  int FindLink(const std::string& name) const;
  int FindFinger(const std::string& name) const;
  double tip_radius() const { return tip_radius_; }
  // Link index pairs (smaller first) that never collide (hand.self_collision_exclude).
  const std::vector<std::pair<int, int>>& collision_exclusions() const { return exclusions_; }
  bool CollisionExcluded(int link_a, int link_b) const;

 private:
  void AssignFingers(const HandParams& params);
  void AssignCollisionExclusions(const HandParams& params);

  std::string urdf_path_;
  std::vector<LinkInfo> links_;
  std::vector<JointInfo> joints_;
  std::vector<FingerInfo> fingers_;
  std::vector<int> actuated_;
  double tip_radius_ = 0.012;
  std::vector<std::pair<int, int>> exclusions_;
};

}  // namespace dmpl
