#pragma once
// The supervisor's messages <-> its core's values, written once: the node translates through
// here (a report into a view, the core's task and state into messages).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dmpl/controller_status_t.hpp"
#include "dmpl/supervisor_status_t.hpp"
#include "dmpl/task_cmd_t.hpp"
#include "supervisor/supervisor.h"

namespace dmpl {

// Why a report is not one the controller can have sent (NaN, beyond the hand's physical
// range), or empty.
std::string OutOfRange(const controller_status_t& m);
// What the supervisor reads of a report (`fingers`: the hand's, in its order; others ignored).
ControllerView ToControllerView(const controller_status_t& m,
                                const std::vector<std::string>& fingers);
// A recorded status fed to a blackboard as the supervisor reads one, for the tools that replay
// what the gait learned from a log: its view, its time, what its contacts teach of the surface.
// The board is made from the status's fingers at the first.
void LearnFromStatus(const controller_status_t& m, std::unique_ptr<Blackboard>* board);
// The controller's task of seq `seq`, with a request to the simulator (run_id left 0: the
// node's to set).
task_cmd_t ToTaskMessage(const TaskInput& t, const std::vector<std::string>& fingers, int64_t seq,
                         int64_t utime, SimRequest sim, const std::string& reason);
// The supervisor's state as its status message.
supervisor_status_t ToStatusMessage(const Supervisor& core, int64_t seq, int64_t utime);

}  // namespace dmpl
