#pragma once
// Factories of every dmpl node: each builds its node from the resolved configuration (and throws
// a ConfigError naming the file and key when it cannot). A node's own executable calls one of
// them through RunNodeMain; the one-process executable calls them all on one memq:// bus.
#include <memory>

#include "components/runtime/node.h"

namespace dmpl {

std::unique_ptr<Node> MakeSimNode(const NodeContext& ctx);
std::unique_ptr<Node> MakeNoiseNode(const NodeContext& ctx);
std::unique_ptr<Node> MakeIkNode(const NodeContext& ctx);
std::unique_ptr<Node> MakeControllerNode(const NodeContext& ctx);
std::unique_ptr<Node> MakeSupervisorNode(const NodeContext& ctx);
std::unique_ptr<Node> MakeJointPlayerNode(const NodeContext& ctx);

}  // namespace dmpl
