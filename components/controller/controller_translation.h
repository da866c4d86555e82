#pragma once
// The controller's messages <-> its core's values, written once: the node translates through
// here and does nothing else with a message's fields.
#include <cstdint>
#include <string>
#include <vector>

#include "components/controller/controller_types.h"
#include "components/kinematics/hand_kinematics.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/task_cmd_t.hpp"

namespace dmpl {

// The sensed input of one tick; the fingers the message does not name keep their `previous`
// readings (one per finger of `kin`).
SensedInput ToSensedInput(const hand_sensors_t& m, const HandKinematics& kin,
                          const std::vector<SensedTip>& previous);
// The task a message carries. Fingers the hand does not have are left out and named in
// `unknown`.
TaskInput ToTaskInput(const task_cmd_t& m, const HandKinematics& kin,
                      std::vector<std::string>* unknown);
// What the IK gets for tick `tick`: each finger's target (or hold), and the sensed joints the
// targets were planned from.
void FillTargets(const ControllerOutput& out, const SensedInput& sensed, int64_t tick,
                 finger_targets_t* targets);
// The controller's status of tick `tick`, with this tick's events.
void FillStatus(const ControllerOutput& out, int64_t tick, int64_t utime,
                const HandKinematics& kin, controller_status_t* status);

}  // namespace dmpl
