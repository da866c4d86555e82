#pragma once
#include <cstdint>
#include <string_view>
// The one table of LCM channel names. Every channel is listed in kChannelBuses below: the build
// prints that table for Python and the shell tools (dmpl_channels_py -> build/python/dmpl_channels.py).
namespace dmpl::channels {

// Simulator -> noise injector: the ground truth of a tick, joints + object + fingertips in one
// hand_sensors_t (only the noise injector and metrics read it).
inline constexpr char kSensorsTrue[] = "DMPL_SENSORS_TRUE";
// Noise injector -> controller, IK, joint player: what a real hand would sense, same type.
inline constexpr char kSensors[] = "DMPL_SENSORS";
// Controller -> IK -> simulator.
inline constexpr char kFingerTargets[] = "DMPL_FINGER_TARGETS";
inline constexpr char kJointCmd[] = "DMPL_JOINT_CMD";
inline constexpr char kIkStatus[] = "DMPL_IK_STATUS";
// Supervisor <-> controller: a report every controller.node.report_period_ticks, answered by a task.
inline constexpr char kTask[] = "DMPL_TASK";
inline constexpr char kControllerReport[] = "DMPL_CONTROLLER_REPORT";
// The controller's status of every tick (logs, calibration, metrics, lcm-spy).
inline constexpr char kControllerStatus[] = "DMPL_CONTROLLER_STATUS";
inline constexpr char kSupervisorStatus[] = "DMPL_SUPERVISOR_STATUS";
// Simulator control and status.
inline constexpr char kSimControl[] = "DMPL_SIM_CONTROL";
inline constexpr char kSimStatus[] = "DMPL_SIM_STATUS";
// For viewers: the truth and the sensed channel at run.view_rate_hz (30 Hz) on a bus of their
// own, so that a viewer costs the loop a few copies per frame, not one per tick.
inline constexpr char kViewTruth[] = "DMPL_VIEW_TRUTH";
inline constexpr char kViewSensed[] = "DMPL_VIEW_SENSED";
// The recorder confirms what it recorded (record_confirm.h): ledgers from the publishers,
// receipts back, on a bus of their own so that no other process wakes for them.
inline constexpr char kRecordLedger[] = "DMPL_RECORD_LEDGER";
inline constexpr char kRecordReceipt[] = "DMPL_RECORD_RECEIPT";
// Process management.
inline constexpr char kHeartbeat[] = "DMPL_HEARTBEAT";
inline constexpr char kProcessStatus[] = "DMPL_PROCESS_STATUS";

// Buses: with a udpm URL each group of channels travels on its own port (base port + 1000 * bus),
// because LCM delivers every packet of a port to every process listening on it: a process then
// wakes only for the channels it may want. Channels whose relative order matters share a bus
// (JOINT_CMD and SIM_CONTROL: a control sent in answer to tick s must reach the simulator before
// the command for tick s + 1).
// The monitor bus carries what only people and tools read (lcm-spy, the recorder), so that no
// process of the loop wakes for it. The supervisor's status (100 Hz) is on the management bus:
// the demo's progress and the live viewer read it without joining the monitor bus's 2 kHz.
inline constexpr int kNumBuses = 10;
inline constexpr const char* kBusNames[kNumBuses] = {
    "management", "truth", "sensed", "targets", "joints", "task",
    "status",     "monitor", "view", "record"};
struct ChannelBus {
  const char* channel;
  int bus;
};
inline constexpr ChannelBus kChannelBuses[] = {
    {kHeartbeat, 0},
    {kProcessStatus, 0},
    {kSimStatus, 0},
    {kSensorsTrue, 1},
    {kSensors, 2},
    {kFingerTargets, 3},
    {kJointCmd, 4},
    {kIkStatus, 7},
    {kSimControl, 4},
    {kTask, 5},
    {kControllerReport, 6},
    {kControllerStatus, 7},
    {kSupervisorStatus, 0},
    {kViewTruth, 8},
    {kViewSensed, 8},
    {kRecordLedger, 9},
    {kRecordReceipt, 9},
};

// The loop's channels: in a run with an identity (run.run_id), a message on one of them without
// the run's identity is not the run's (only a node started by hand, with no identity, takes
// messages sent by hand). Control channels (SIM_CONTROL) still take a message sent by hand.
inline constexpr const char* kLoopChannels[] = {kSensorsTrue, kSensors,    kFingerTargets,
                                                kJointCmd,    kTask,       kControllerReport};
inline bool IsLoopChannel(std::string_view channel) {
  for (const char* c : kLoopChannels) {
    if (channel == c) return true;
  }
  return false;
}

// Whether a process of run `own` takes a message of run `theirs` (0: no identity) on a channel:
// the same run, or no identity on this side (a node started by hand), or, except on the loop's
// channels, none on the message's (sent by hand). Nodes and the recorder share this rule.
inline bool OfRun(int64_t own, int64_t theirs, bool loop_channel) {
  return own == 0 || theirs == own || (theirs == 0 && !loop_channel);
}

}  // namespace dmpl::channels
