#pragma once
// The dmpl_noise node: the noise injector (truth -> sensed channels). Its executable (noise_main.cc) and the one-process executable
// (tools/oneprocess) both build it from this description.
#include "components/runtime/node.h"

namespace dmpl {

extern const NodeInfo kNoiseNode;

}  // namespace dmpl
