#pragma once
// The dmpl_supervisor node: the regrasp supervisor. Its executable (supervisor_main.cc) and the one-process executable
// (tools/oneprocess) both build it from this description.
#include "components/runtime/node.h"

namespace dmpl {

extern const NodeInfo kSupervisorNode;

}  // namespace dmpl
