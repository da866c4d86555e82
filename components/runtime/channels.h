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

}  // namespace dmpl::channels
