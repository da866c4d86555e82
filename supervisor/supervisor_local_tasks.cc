// The local tasks of a task file: each finger through its PTask sequence, FIstate checks and
// transition conditions.
#include "supervisor/supervisor.h"

#include <string>

#include "components/runtime/check.h"

namespace dmpl {

bool Supervisor::InState(const FIstate& state, int finger, Role role) const {
  const bool touching = view_.fingers[finger].in_contact;
  if ((state.contact == ContactState::kTouching && !touching) ||
      (state.contact == ContactState::kFree && touching)) {
    return false;
  }
  return !state.role || *state.role == role;
}

bool Supervisor::ConditionHolds(Condition c, int finger) const {
  switch (c) {
    case Condition::kNone: return false;
    case Condition::kContact: return finger >= 0 && view_.fingers[finger].in_contact;
    case Condition::kTargetReached: return finger >= 0 && reached_[finger];
    case Condition::kGraspStable: return view_.grasp_stable;
    case Condition::kMotionDone: return motion_done_event_ || view_.motion_done;
    case Condition::kDuration: return false;  // checked by the caller against its duration
  }
  return false;
}

void Supervisor::TickLocalTask() {
  const CTask& task = tasks_.tasks[task_index_];
  // Each finger moves through its PTask sequence.
  for (size_t f = 0; f < fingers_.size(); ++f) {
    auto it = task.fingers.find(fingers_[f]);
    if (it == task.fingers.end()) it = task.fingers.find("all");
    if (it == task.fingers.end()) continue;
    const std::vector<PTask>& seq = it->second;
    int& i = ptask_index_[f];
    if (i + 1 >= static_cast<int>(seq.size())) continue;
    const PTask& p = seq[i];
    const bool done = p.until == Condition::kDuration
                          ? now_ - ptask_since_[f] >= p.duration_s
                          : ConditionHolds(p.until, static_cast<int>(f));
    if (!done) continue;
    if (!InState(p.exit, static_cast<int>(f), p.role)) {
      Note("task '" + task.name + "': finger " + fingers_[f] + " is not in its exit state");
    }
    const PTask& next = seq[++i];
    ptask_since_[f] = now_;
    const double force =
        next.role == Role::kExplore && next.force_n <= 0 ? task_params_.explore_force_n : next.force_n;
    SetFinger(static_cast<int>(f), next.role, next.primitive, next.has_target ? &next.target : nullptr,
              force);
    out_.changed = true;
  }
  const bool done = task.done_when == Condition::kDuration
                        ? now_ - task_since_ >= task.duration_s
                        : ConditionHolds(task.done_when, -1);
  if (done) {
    grasp_.Process(GraspEvent::TaskDone);
  } else if (now_ - task_since_ > task.timeout_s) {
    grasp_.Process(GraspEvent::TaskFailed, {"task '" + task.name + "' did not finish within " +
                                            std::to_string(task.timeout_s) + " s"});
  }
}

}  // namespace dmpl
