#pragma once
// What the loop asks of the simulator: one vocabulary for the supervisor that requests and the
// simulator that obeys. The codes are sim_control_t's (and task_cmd_t/joint_cmd_t's sim_command),
// so a request crosses the bus as static_cast<int8_t>(request).
#include <cstdint>

namespace dmpl {

enum class SimRequest : int8_t {
  kNone = 0,
  kRelease = 1,  // let go of a held object
  kHold = 2,     // hold the object fixed where it is
  kReset = 3,    // back to the initial scenario
  kPause = 4,
  kResume = 5,
  kStop = 6,     // end the run
};

const char* ToString(SimRequest request);

}  // namespace dmpl
