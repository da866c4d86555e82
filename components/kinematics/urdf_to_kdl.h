#pragma once
// Our own urdfdom -> KDL::Tree converter (Debian's kdl_parser drags in ROS 1). The hand model is
// the urdfdom parse (components/hand/hand_model.h, which already rejects floating and planar
// joints); revolute and continuous joints become KDL rotational joints with the axis expressed in
// the parent frame, fixed joints fixed. KDL stores no joint limits: HandModel keeps them.
#include <kdl/tree.hpp>

#include "components/hand/hand_model.h"

namespace dmpl {

KDL::Tree UrdfToKdlTree(const HandModel& model);

}  // namespace dmpl
