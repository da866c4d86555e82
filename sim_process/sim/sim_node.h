#pragma once
// The dmpl_sim node: the simulator of the hand and the object. Its executable (sim_main.cc) and the one-process executable
// (tools/oneprocess) both build it from this description.
#include "components/runtime/node.h"

namespace dmpl {

extern const NodeInfo kSimNode;

}  // namespace dmpl
