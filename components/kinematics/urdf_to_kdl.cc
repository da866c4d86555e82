#include "components/kinematics/urdf_to_kdl.h"

#include <kdl/frames.hpp>

#include "components/runtime/check.h"

namespace dmpl {
namespace {

KDL::Frame ToKdl(const Eigen::Isometry3d& t) {
  const Eigen::Matrix3d& r = t.linear();
  return KDL::Frame(KDL::Rotation(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0),
                                  r(2, 1), r(2, 2)),
                    KDL::Vector(t.translation().x(), t.translation().y(), t.translation().z()));
}

KDL::RigidBodyInertia ToKdlInertia(const LinkInfo& link) {
  const Eigen::Matrix3d& i = link.inertia;
  return KDL::RigidBodyInertia(
      link.mass, KDL::Vector(link.com.x(), link.com.y(), link.com.z()),
      KDL::RotationalInertia(i(0, 0), i(1, 1), i(2, 2), i(0, 1), i(0, 2), i(1, 2)));
}

}  // namespace

KDL::Tree UrdfToKdlTree(const HandModel& model) {
  const auto& links = model.links();
  KDL::Tree tree(links[0].name);
  for (size_t l = 1; l < links.size(); ++l) {
    const LinkInfo& link = links[l];
    const JointInfo& j = model.joints()[link.parent_joint];
    const KDL::Frame origin = ToKdl(j.origin);
    KDL::Joint joint(j.name, KDL::Joint::Fixed);
    if (j.type == JointInfo::Type::kRevolute) {
      const KDL::Vector axis_in_parent = origin.M * KDL::Vector(j.axis.x(), j.axis.y(), j.axis.z());
      joint = KDL::Joint(j.name, origin.p, axis_in_parent, KDL::Joint::RotAxis);
    }
    const KDL::Segment segment(link.name, joint, origin, ToKdlInertia(link));
    // Parents come before children in HandModel, so the hook always exists.
    DMPL_DEMAND(tree.addSegment(segment, links[link.parent_link].name));
  }
  return tree;
}

}  // namespace dmpl
