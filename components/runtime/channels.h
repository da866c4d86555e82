#pragma once
// The one table of LCM channel names. tools/python reads this file, so keep the form
// `inline constexpr char kName[] = "DMPL_...";` one per line.
namespace dmpl::channels {

// Simulator -> noise injector (ground truth; only the noise injector and metrics read these).
inline constexpr char kHandStateTrue[] = "DMPL_HAND_STATE_TRUE";
inline constexpr char kObjectPoseTrue[] = "DMPL_OBJECT_POSE_TRUE";
inline constexpr char kTactileTrue[] = "DMPL_TACTILE_TRUE";
// Noise injector -> controller, IK (what a real hand would sense).
inline constexpr char kHandState[] = "DMPL_HAND_STATE";
inline constexpr char kObjectPose[] = "DMPL_OBJECT_POSE";
inline constexpr char kTactile[] = "DMPL_TACTILE";
// Controller -> IK -> simulator.
inline constexpr char kFingerTargets[] = "DMPL_FINGER_TARGETS";
inline constexpr char kJointCmd[] = "DMPL_JOINT_CMD";
inline constexpr char kIkStatus[] = "DMPL_IK_STATUS";
// Supervisor <-> controller.
inline constexpr char kTask[] = "DMPL_TASK";
inline constexpr char kControllerStatus[] = "DMPL_CONTROLLER_STATUS";
inline constexpr char kSupervisorStatus[] = "DMPL_SUPERVISOR_STATUS";
// Simulator control and status.
inline constexpr char kSimControl[] = "DMPL_SIM_CONTROL";
inline constexpr char kSimStatus[] = "DMPL_SIM_STATUS";
// Process management.
inline constexpr char kHeartbeat[] = "DMPL_HEARTBEAT";
inline constexpr char kProcessStatus[] = "DMPL_PROCESS_STATUS";

// Buses: with a udpm URL each group of channels travels on its own port (base port + 1000 * bus),
// because LCM delivers every packet of a port to every process listening on it: a process then
// wakes only for the channels it may want. Keep the form `{kName, bus},` one per line (tools/python
// reads it). Channels whose relative order matters share a bus (JOINT_CMD and SIM_CONTROL: a
// control sent in answer to tick s must reach the simulator before the command for tick s + 1).
inline constexpr int kNumBuses = 8;
inline constexpr const char* kBusNames[kNumBuses] = {
    "management", "truth", "sensed", "joint_state", "targets", "joints", "task", "status"};
struct ChannelBus {
  const char* channel;
  int bus;
};
inline constexpr ChannelBus kChannelBuses[] = {
    {kHeartbeat, 0},
    {kProcessStatus, 0},
    {kSimStatus, 0},
    {kHandStateTrue, 1},
    {kObjectPoseTrue, 1},
    {kTactileTrue, 1},
    {kObjectPose, 2},
    {kTactile, 2},
    {kHandState, 3},
    {kFingerTargets, 4},
    {kJointCmd, 5},
    {kIkStatus, 5},
    {kSimControl, 5},
    {kTask, 6},
    {kControllerStatus, 7},
    {kSupervisorStatus, 7},
};

}  // namespace dmpl::channels
