#pragma once
// The dmpl_joint_player node: joint trajectories played to the simulator. Its executable (joint_player_main.cc) and the one-process executable
// (tools/oneprocess) both build it from this description.
#include "components/runtime/node.h"

namespace dmpl {

extern const NodeInfo kJointPlayerNode;

}  // namespace dmpl
