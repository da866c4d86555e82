#include "components/hand/hand_model.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>

#include <Eigen/Eigenvalues>
#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

namespace dmpl {
namespace {

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  t.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y,
                                  pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

[[noreturn]] void FailUrdf(const std::string& file, const std::string& what) {
  throw ConfigError("URDF error in " + file + ": " + what);
}

// urdfdom says why a file does not parse through console_bridge, on stderr by default: kept here
// to go into the error instead (the handler is process-wide, hence the lock).
class KeepMessages : public console_bridge::OutputHandler {
 public:
  KeepMessages() { console_bridge::useOutputHandler(this); }
  ~KeepMessages() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
    text_ += (text_.empty() ? "" : "; ") + text;
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

urdf::ModelInterfaceSharedPtr ParseUrdf(const std::string& file, std::string* messages) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  KeepMessages keep;
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(file);
  *messages = keep.text().empty() ? "(it gave no reason)" : keep.text();
  return model;
}

// A link's mass, centre of mass and inertia (about the com, in the link frame's axes).
void ReadInertial(const std::string& file, const urdf::Link& link, LinkInfo* info) {
  const urdf::Inertial& in = *link.inertial;
  if (!(in.mass > 0.0) || !std::isfinite(in.mass)) {
    FailUrdf(file, "link '" + link.name + "' has a non-positive mass " + std::to_string(in.mass));
  }
  info->mass = in.mass;
  const Eigen::Isometry3d frame = ToIsometry(in.origin);
  info->com = frame.translation();
  Eigen::Matrix3d i_frame;
  i_frame << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  info->inertia = frame.linear() * i_frame * frame.linear().transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(info->inertia);
  if (eig.eigenvalues().minCoeff() <= 0.0) {
    FailUrdf(file, "link '" + link.name + "' has an inertia that is not positive definite");
  }
}

CollisionShape ReadCollision(const std::string& file, const urdf::Link& link,
                             const urdf::Collision& c) {
  CollisionShape shape;
  shape.origin = ToIsometry(c.origin);
  switch (c.geometry->type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(*c.geometry);
      shape.kind = CollisionShape::Kind::kBox;
      shape.box_size = Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z);
      return shape;
    }
    case urdf::Geometry::SPHERE:
      shape.kind = CollisionShape::Kind::kSphere;
      shape.radius = static_cast<const urdf::Sphere&>(*c.geometry).radius;
      return shape;
    case urdf::Geometry::CYLINDER: {
      const auto& cyl = static_cast<const urdf::Cylinder&>(*c.geometry);
      shape.kind = CollisionShape::Kind::kCylinder;
      shape.radius = cyl.radius;
      shape.length = cyl.length;
      return shape;
    }
    default:
      FailUrdf(file, "link '" + link.name + "': only box, sphere and cylinder collisions are "
               "supported (meshes are not)");
  }
}

// A revolute (or continuous) joint's axis, limits, effort and speed.
void ReadRevolute(const std::string& file, const urdf::Joint& uj, JointInfo* joint) {
  joint->type = JointInfo::Type::kRevolute;
  const Eigen::Vector3d axis(uj.axis.x, uj.axis.y, uj.axis.z);
  if (axis.norm() < 1e-9) FailUrdf(file, "joint '" + uj.name + "' has a zero axis");
  joint->axis = axis.normalized();
  if (uj.type == urdf::Joint::CONTINUOUS) {
    joint->lower = -std::numeric_limits<double>::infinity();
    joint->upper = std::numeric_limits<double>::infinity();
  } else {
    if (!uj.limits) FailUrdf(file, "revolute joint '" + uj.name + "' has no <limit>");
    joint->lower = uj.limits->lower;
    joint->upper = uj.limits->upper;
    if (!(joint->lower < joint->upper)) {
      FailUrdf(file, "joint '" + uj.name + "' has lower limit >= upper limit");
    }
  }
  if (uj.limits) {
    joint->effort = uj.limits->effort;
    joint->velocity = uj.limits->velocity;
  }
  if (!(joint->effort > 0.0)) FailUrdf(file, "joint '" + uj.name + "' needs an effort limit > 0");
}

JointInfo ReadJoint(const std::string& file, const urdf::Joint& uj, int parent_link) {
  JointInfo joint;
  joint.name = uj.name;
  joint.parent_link = parent_link;
  joint.origin = ToIsometry(uj.parent_to_joint_origin_transform);
  switch (uj.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      ReadRevolute(file, uj, &joint);
      return joint;
    case urdf::Joint::FIXED:
      joint.type = JointInfo::Type::kFixed;
      return joint;
    case urdf::Joint::FLOATING:
      FailUrdf(file, "joint '" + uj.name + "' is floating: not supported (the palm is fixed)");
    case urdf::Joint::PLANAR:
      FailUrdf(file, "joint '" + uj.name + "' is planar: not supported");
    case urdf::Joint::PRISMATIC:
      FailUrdf(file, "joint '" + uj.name + "' is prismatic: not supported by this hand model");
    default:
      FailUrdf(file, "joint '" + uj.name + "' has an unknown type");
  }
}

// Depth-first from `link`: parents before children, children in URDF order.
void AppendSubtree(const std::string& file, const urdf::LinkConstSharedPtr& link,
                   int parent_link, int parent_joint, std::vector<LinkInfo>* links,
                   std::vector<JointInfo>* joints) {
  LinkInfo info;
  info.name = link->name;
  info.parent_link = parent_link;
  info.parent_joint = parent_joint;
  if (link->inertial) {
    ReadInertial(file, *link, &info);
  } else if (parent_link >= 0) {
    FailUrdf(file, "link '" + link->name + "' has no <inertial> (every moving link needs a mass)");
  }
  for (const auto& c : link->collision_array) {
    if (c && c->geometry) info.collisions.push_back(ReadCollision(file, *link, *c));
  }
  const int index = static_cast<int>(links->size());
  links->push_back(info);
  for (const auto& child : link->child_links) {
    JointInfo joint = ReadJoint(file, *child->parent_joint, index);
    joint.child_link = static_cast<int>(links->size());
    const int joint_index = static_cast<int>(joints->size());
    joints->push_back(joint);
    AppendSubtree(file, child, index, joint_index, links, joints);
  }
}

}  // namespace

std::string ResolveProjectPath(const std::string& path) {
  if (path.empty() || path[0] == '/') return path;
  if (const char* root = std::getenv("DMPL_ROOT"); root && *root) {
    return (std::filesystem::path(root) / path).string();
  }
  return path;
}

std::vector<std::string> HandModel::actuated_names() const {
  std::vector<std::string> names;
  for (int j : actuated_) names.push_back(joints_[j].name);
  return names;
}

int HandModel::FindLink(const std::string& name) const {
  for (size_t i = 0; i < links_.size(); ++i) {
    if (links_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int HandModel::FindFinger(const std::string& name) const {
  for (size_t i = 0; i < fingers_.size(); ++i) {
    if (fingers_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

bool HandModel::CollisionExcluded(int link_a, int link_b) const {
  const std::pair<int, int> pair(std::min(link_a, link_b), std::max(link_a, link_b));
  return std::find(exclusions_.begin(), exclusions_.end(), pair) != exclusions_.end();
}

HandModel HandModel::Load(const HandParams& params) {
  HandModel model;
  model.urdf_path_ = ResolveProjectPath(params.urdf);
  model.tip_radius_ = params.tip_radius;
  const std::string& file = model.urdf_path_;
  if (!std::filesystem::exists(file)) {
    throw ConfigError("URDF error: file '" + file + "' does not exist (key hand.urdf)");
  }
  std::string why;
  const urdf::ModelInterfaceSharedPtr urdf = ParseUrdf(file, &why);
  if (!urdf) FailUrdf(file, "urdfdom could not parse it: " + why);
  if (!urdf->getRoot()) FailUrdf(file, "no root link");
  AppendSubtree(file, urdf->getRoot(), -1, -1, &model.links_, &model.joints_);
  model.AssignFingers(params);
  model.AssignCollisionExclusions(params);
  return model;
}

void HandModel::AssignFingers(const HandParams& params) {
  // Chains from the root to each tip link; actuated joints numbered finger by finger.
  if (params.fingers.empty()) throw ConfigError("config error: hand.fingers is empty");
  std::vector<bool> claimed(joints_.size(), false);
  for (const auto& fp : params.fingers) {
    FingerInfo finger;
    finger.name = fp.name;
    finger.tip_link = FindLink(fp.tip_link);
    if (finger.tip_link < 0) {
      FailUrdf(urdf_path_,
               "finger '" + fp.name + "': tip link '" + fp.tip_link + "' is not in the URDF");
    }
    for (int l = finger.tip_link; links_[l].parent_link >= 0; l = links_[l].parent_link) {
      finger.links.insert(finger.links.begin(), l);
    }
    for (int l : finger.links) {
      const int j = links_[l].parent_joint;
      if (joints_[j].type != JointInfo::Type::kRevolute) continue;
      if (claimed[j]) FailUrdf(urdf_path_, "joint '" + joints_[j].name + "' is on two fingers' chains");
      claimed[j] = true;
      joints_[j].actuated_index = static_cast<int>(actuated_.size());
      finger.joints.push_back(joints_[j].actuated_index);
      actuated_.push_back(j);
    }
    if (finger.joints.empty()) FailUrdf(urdf_path_, "finger '" + fp.name + "' has no revolute joints");
    fingers_.push_back(finger);
  }
  for (size_t j = 0; j < joints_.size(); ++j) {
    if (joints_[j].type == JointInfo::Type::kRevolute && !claimed[j]) {
      FailUrdf(urdf_path_, "revolute joint '" + joints_[j].name + "' is on no finger's chain");
    }
  }
}

void HandModel::AssignCollisionExclusions(const HandParams& params) {
  for (size_t i = 0; i < params.self_collision_exclude.size(); ++i) {
    const auto& [a, b] = params.self_collision_exclude[i];
    const int la = FindLink(a), lb = FindLink(b);
    const std::string key = "hand.self_collision_exclude[" + std::to_string(i) + "]";
    if (la < 0 || lb < 0) {
      throw ConfigError("config error: key '" + key + "': link '" + (la < 0 ? a : b) +
                        "' is not in " + urdf_path_);
    }
    if (la == lb) throw ConfigError("config error: key '" + key + "': a link with itself");
    exclusions_.emplace_back(std::min(la, lb), std::max(la, lb));
  }
}

}  // namespace dmpl
