#include "components/kinematics/finger_links.h"

#include <cmath>

#include "components/runtime/check.h"

namespace dmpl {

LinkCapsule EnclosingCapsule(const CollisionShape& shape) {
  LinkCapsule c;
  Eigen::Vector3d half_axis = Eigen::Vector3d::Zero();
  switch (shape.kind) {
    case CollisionShape::Kind::kSphere:
      c.radius = shape.radius;
      break;
    case CollisionShape::Kind::kCylinder:
      c.radius = shape.radius;
      half_axis = Eigen::Vector3d(0, 0, shape.length / 2);
      break;
    case CollisionShape::Kind::kBox: {
      const Eigen::Vector3d& size = shape.box_size;
      int longest = 0;
      size.maxCoeff(&longest);
      half_axis[longest] = size[longest] / 2;
      const int u = (longest + 1) % 3, v = (longest + 2) % 3;
      c.radius = 0.5 * std::hypot(size[u], size[v]);
      break;
    }
  }
  c.a = shape.origin * (-half_axis);
  c.b = shape.origin * half_axis;
  return c;
}

FingerLinks::FingerLinks(const HandModel& model, const FingerKinematics& finger)
    : finger_(finger) {
  for (int k = 0; k < finger.num_links(); ++k) {
    const int link = model.FindLink(finger.LinkName(k));
    DMPL_DEMAND(link >= 0);
    for (const CollisionShape& shape : model.links()[link].collisions) {
      LinkCapsule c = EnclosingCapsule(shape);
      c.link = finger.LinkName(k);
      c.tip = k == finger.num_links() - 1;
      chain_link_.push_back(k);
      local_.push_back(c);
    }
  }
}

std::vector<LinkCapsule> FingerLinks::Capsules(const Eigen::VectorXd& q) const {
  std::vector<Eigen::Isometry3d> frames;
  finger_.LinkFrames(q, &frames);
  std::vector<LinkCapsule> out = local_;
  for (size_t i = 0; i < out.size(); ++i) {
    const Eigen::Isometry3d& frame = frames[chain_link_[i]];
    out[i].a = frame * local_[i].a;
    out[i].b = frame * local_[i].b;
  }
  return out;
}

}  // namespace dmpl
