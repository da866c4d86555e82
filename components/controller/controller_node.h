#pragma once
// The dmpl_controller node: the local manipulation controller. Its executable (controller_main.cc) and the one-process executable
// (tools/oneprocess) both build it from this description.
#include "components/runtime/node.h"

namespace dmpl {

extern const NodeInfo kControllerNode;

}  // namespace dmpl
