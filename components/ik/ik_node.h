#pragma once
// The dmpl_ik node: the IK server. Its executable (ik_main.cc) and the one-process executable
// (tools/oneprocess) both build it from this description.
#include "components/runtime/node.h"

namespace dmpl {

extern const NodeInfo kIkNode;

}  // namespace dmpl
