#include "sim_process/sim/sim_scheduler.h"

#include <utility>

namespace dmpl {

SimScheduler::SimScheduler(const SimScheduleParams& params, SimLoop* loop)
    : params_(params), loop_(loop) {}

void SimScheduler::Begin(double now) {
  if (started_) return;
  started_ = true;
  loop_->PublishTick(tick_);
  published_at_ = now;
  if (params_.lockstep) StepWhileReady(now);
}

SimScheduler::Verdict SimScheduler::OnCommand(JointCommand command, double now) {
  // Before the start nothing can be due; in lockstep only the due command and those of ticks
  // already published can be useful.
  const bool useless = params_.lockstep && (command.seq < due_seq() || command.seq > tick_ ||
                                            commands_.count(command.seq) != 0);
  if (!started_ || useless) {
    ++stale_;
    return Verdict::kStale;
  }
  if (params_.lockstep) {
    commands_.emplace(command.seq, std::move(command));
    StepWhileReady(now);
    return Verdict::kQueued;
  }
  if (command.seq > tick_) return Verdict::kAhead;  // so at most d commands wait
  const int64_t seq = command.seq;
  commands_[seq] = std::move(command);  // a repeat replaces the one not yet applied
  ApplyDueCommands(now);
  return Verdict::kQueued;
}

bool SimScheduler::OnControl(SimControl control, double now) {
  // A control carrying seq s (sent in answer to tick s) acts before the step that applies the
  // command of tick s + 1: its sender answered tick s before anyone could answer s + 1, and it
  // shares JOINT_CMD's bus, so it lands at the same tick in every run, one process or many.
  if (control.seq < 0) control.seq = due_seq() - 1;
  const bool on_time = !params_.lockstep || control.seq >= due_seq() - 1;
  if (control.command == SimRequest::kPause || control.command == SimRequest::kResume) {
    Apply(control, now);  // these act on the loop itself, now
    if (control.command == SimRequest::kResume && params_.lockstep) StepWhileReady(now);
    return on_time;
  }
  controls_.push_back(std::move(control));
  return on_time;
}

void SimScheduler::CheckTimeout(double now) {
  if (!params_.lockstep || !started_ || paused_ || finished_) return;
  if (now - published_at_ < params_.tick_timeout_s) return;
  ++faults_;
  published_at_ = now;
  loop_->Fault("lockstep fault: no JOINT_CMD for seq " + std::to_string(due_seq()) + " within " +
               std::to_string(params_.tick_timeout_s) + " s");
  if (faults_ >= params_.max_tick_faults) Finish(nullptr, true);
}

bool SimScheduler::AdvanceRealTime(double now) {
  if (!started_ || paused_ || finished_) return false;
  ApplyDueCommands(now);
  Advance(now);
  return !finished_ && !paused_;
}

// Lockstep: steps for as long as the command each step needs has arrived (with a delay the
// commands of the next ticks may already be in).
void SimScheduler::StepWhileReady(double now) {
  while (started_ && !paused_ && !finished_) {
    const int64_t due = due_seq();
    if (due >= 0) {
      const auto it = commands_.find(due);
      if (it == commands_.end()) return;
      const JointCommand command = std::move(it->second);
      commands_.erase(it);  // the earliest: older ones are refused as stale
      ApplyCommand(command, now);
    } else if (tick_ == 0 && params_.first_tick_waits && commands_.empty()) {
      // Every node then starts its stream at tick 0, and a lost first message is sent again
      // rather than overtaken.
      return;
    }
    Advance(now);
  }
}

void SimScheduler::ApplyDueCommands(double now) {
  while (!commands_.empty() && commands_.begin()->first <= due_seq() && !finished_) {
    const JointCommand command = std::move(commands_.begin()->second);
    commands_.erase(commands_.begin());
    ApplyCommand(command, now);
  }
}

void SimScheduler::ApplyCommand(const JointCommand& command, double now) {
  loop_->ApplyCommand(command);
  if (command.request == SimRequest::kNone) return;
  // The task's request, planned with this command: it acts now, before the step that applies
  // the command, as a control of seq - 1 would.
  SimControl control;
  control.seq = command.seq - 1;
  control.command = command.request;
  control.reason = "the task's, with joint command " + std::to_string(command.seq);
  Apply(control, now);
}

void SimScheduler::ApplyDueControls(double now) {
  while (!controls_.empty() && controls_.front().seq < due_seq() && !finished_) {
    const SimControl control = std::move(controls_.front());
    controls_.pop_front();
    Apply(control, now);
  }
}

void SimScheduler::Apply(const SimControl& control, double now) {
  switch (control.command) {
    case SimRequest::kPause:
      if (!paused_) {
        paused_ = true;
        paused_since_ = now;
        loop_->Paused(control);
      }
      return;
    case SimRequest::kResume:
      if (paused_) {
        paused_ = false;
        published_at_ = now;  // the wait for the due command starts again
        loop_->Resumed(control, now - paused_since_);
      }
      return;
    case SimRequest::kStop:
      Finish(&control, false);
      return;
    default:
      loop_->ApplyControl(control);
  }
}

void SimScheduler::Advance(double now) {
  ApplyDueControls(now);
  if (finished_) return;  // a STOP
  ++tick_;
  const bool end = loop_->StepTo(tick_);
  published_at_ = now;
  if (end) Finish(nullptr, false);
}

void SimScheduler::Finish(const SimControl* stop, bool gave_up) {
  if (finished_) return;
  finished_ = true;
  loop_->Finished(stop, gave_up || faults_ >= params_.max_tick_faults);
}

}  // namespace dmpl
