#pragma once
// The simulator's loop apart from its physics and its bus: which joint command each step
// applies, when a control acts, pause and resume, and when a missing command is a fault.
//
// Lockstep: tick k is published; the step from k to k + 1 applies the command with seq k - d
// (d = the actuation delay; before tick d nothing, the initial targets hold) and waits until it
// has arrived. Only the due command and those of ticks already published are kept; anything
// older, newer or repeated is stale. A control of seq s acts before the step that applies the
// command of tick s + 1. Real time: the caller steps on its clock; every command that is due
// (seq <= k - d) is applied in order, the latest winning.
//
// Pure: no bus, no physics, no clock of its own (the caller passes `now`), so every rule above
// has a unit test.
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "components/runtime/sim_request.h"

namespace dmpl {

struct JointCommand {
  int64_t seq = 0;  // answers the truth of this tick
  std::vector<std::string> names;
  std::vector<double> positions;  // rad
  SimRequest request = SimRequest::kNone;  // the task's, applied with this command
};

struct SimControl {
  int64_t seq = -1;  // < 0: at the next step
  SimRequest command = SimRequest::kNone;
  std::string reason;
};

struct SimScheduleParams {
  bool lockstep = true;
  int command_delay_ticks = 0;
  bool first_tick_waits = false;  // lockstep: tick 1 waits for tick 0's answer (lost ones resent)
  double tick_timeout_s = 2.0;    // lockstep: a command missing this long is a fault
  int max_tick_faults = 5;        // lockstep: the run ends after this many
};

// What the scheduler drives (the simulator node; a recording fake in tests).
class SimLoop {
 public:
  virtual ~SimLoop() = default;
  virtual void PublishTick(int64_t tick) = 0;  // the truth of this tick
  virtual void ApplyCommand(const JointCommand& command) = 0;
  virtual void ApplyControl(const SimControl& control) = 0;  // release, hold, reset, unknown
  // One tick of physics, then the truth of tick `new_tick` published. True: the run's end.
  virtual bool StepTo(int64_t new_tick) = 0;
  virtual void Paused(const SimControl& cause) = 0;
  virtual void Resumed(const SimControl& cause, double paused_for_s) = 0;
  virtual void Fault(const std::string& what) = 0;  // a missing command, said with its seq
  // The loop is over: a STOP (`stop` set), the run's end, or too many faults (`gave_up`).
  virtual void Finished(const SimControl* stop, bool gave_up) = 0;
};

class SimScheduler {
 public:
  enum class Verdict { kQueued, kStale, kAhead };

  SimScheduler(const SimScheduleParams& params, SimLoop* loop);

  // Publishes tick 0 and, in lockstep, steps as far as the commands already in allow.
  void Begin(double now);
  Verdict OnCommand(JointCommand command, double now);
  // Pause and resume act at once; the others are queued for their tick. Returns false for a
  // lockstep control that arrived after its tick (it is applied at the next step).
  bool OnControl(SimControl control, double now);
  // Lockstep: a fault when the due command has been missing for tick_timeout_s since the last
  // publication (or the last fault); after max_tick_faults the loop finishes.
  void CheckTimeout(double now);
  // Real time: one tick (due commands, due controls, the step). False once paused or finished.
  bool AdvanceRealTime(double now);

  int64_t tick() const { return tick_; }
  int64_t due_seq() const { return tick_ - params_.command_delay_ticks; }
  bool started() const { return started_; }
  bool paused() const { return paused_; }
  double paused_since() const { return paused_since_; }  // the `now` of the pause
  bool finished() const { return finished_; }
  int faults() const { return faults_; }
  int64_t stale() const { return stale_; }
  size_t waiting_commands() const { return commands_.size(); }

 private:
  void StepWhileReady(double now);
  void ApplyDueCommands(double now);
  void ApplyCommand(const JointCommand& command, double now);
  void ApplyDueControls(double now);
  void Apply(const SimControl& control, double now);
  void Advance(double now);
  void Finish(const SimControl* stop, bool gave_up);

  SimScheduleParams params_;
  SimLoop* loop_;
  std::map<int64_t, JointCommand> commands_;  // by seq, not yet applied
  std::deque<SimControl> controls_;           // in arrival order, not yet applied
  int64_t tick_ = 0;
  bool started_ = false;
  bool paused_ = false;
  bool finished_ = false;
  double paused_since_ = 0;
  double published_at_ = 0;  // the last publication (or fault): where the timeout counts from
  int faults_ = 0;
  int64_t stale_ = 0;
};

}  // namespace dmpl
