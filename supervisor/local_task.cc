#include "supervisor/local_task.h"

#include <algorithm>

namespace dmpl {

LocalTask::LocalTask(Blackboard* board, ObjectGoal* goal, const TaskParams& params,
                     Report report, std::function<void()> all_turn)
    : board_(board),
      goal_(goal),
      params_(params),
      report_(std::move(report)),
      all_turn_(std::move(all_turn)),
      ptask_index_(board->fingers.size(), 0),
      ptask_since_(board->fingers.size(), 0.0) {}

void LocalTask::Start(const CTask& task, double speed) {
  since_ = board_->now;
  board_->NewTask(task.name);
  rotation_at_start_ = goal_->commanded();
  board_->motion_done_event = false;
  std::fill(ptask_index_.begin(), ptask_index_.end(), 0);
  std::fill(ptask_since_.begin(), ptask_since_.end(), board_->now);
  if (task.type == TaskType::kGait) return;
  for (int f = 0; f < board_->num_fingers(); ++f) {
    const std::vector<PTask>* seq = Sequence(task, f);
    if (seq == nullptr) {
      board_->SetFinger(f, Role::kGrip, Primitive::kComposite);
      continue;
    }
    const PTask& p = seq->front();
    if (!InState(p.entry, f, board_->out.task.fingers[f].role)) {
      board_->Note("task '" + task.name + "': finger " + board_->fingers[f] +
                   " is not in its entry state");
    }
    Enter(f, p);
  }
  StartMotion(task, speed);
}

void LocalTask::StartMotion(const CTask& task, double speed) {
  if (!task.motion) {
    goal_->Send();
    return;
  }
  const ObjectMotion& m = *task.motion;
  if (m.reference == ObjectMotion::Reference::kStart) {
    goal_->TurnBackToStart(speed);
  } else {
    goal_->Turn(Axis(m.axis), m.angle * (m.angle_in_task_units ? params_.angle : 1.0), speed);
  }
  if (m.max_angular_speed > 0) board_->out.task.max_angular_speed = m.max_angular_speed;
  goal_->CommandInAll(0.0);
  const auto& fingers = board_->out.task.fingers;
  if (std::all_of(fingers.begin(), fingers.end(),
                  [](const FingerTask& t) { return t.role == Role::kGrip; })) {
    all_turn_();
  }
}

void LocalTask::Resume(const CTask& task, double speed) {
  const double done = goal_->commanded() - rotation_at_start_;
  Start(task, speed);
  if (task.motion && task.motion->reference == ObjectMotion::Reference::kCurrent) {
    goal_->Turn(Axis(task.motion->axis), -done, speed);
    goal_->CommandInAll(0.0);
  }
}

const std::vector<PTask>* LocalTask::Sequence(const CTask& task, int f) const {
  auto it = task.fingers.find(board_->fingers[f]);
  if (it == task.fingers.end()) it = task.fingers.find("all");
  return it == task.fingers.end() ? nullptr : &it->second;
}

void LocalTask::Enter(int f, const PTask& p) {
  const double force =
      p.role == Role::kExplore && p.force_n <= 0 ? params_.explore_force_n : p.force_n;
  board_->SetFinger(f, p.role, p.primitive, p.has_target ? &p.target : nullptr, force);
}

void LocalTask::Tick(const CTask& task) {
  // Each finger moves through its PTask sequence.
  for (int f = 0; f < board_->num_fingers(); ++f) {
    const std::vector<PTask>* seq = Sequence(task, f);
    if (seq == nullptr) continue;
    int& i = ptask_index_[f];
    if (i + 1 >= static_cast<int>(seq->size())) continue;
    const PTask& p = (*seq)[i];
    const bool done = p.until == Condition::kDuration
                          ? board_->now - ptask_since_[f] >= p.duration_s
                          : ConditionHolds(p.until, f);
    if (!done) continue;
    if (!InState(p.exit, f, p.role)) {
      board_->Note("task '" + task.name + "': finger " + board_->fingers[f] +
                   " is not in its exit state");
    }
    ptask_since_[f] = board_->now;
    Enter(f, (*seq)[++i]);
    board_->out.changed = true;
  }
  const bool done = task.done_when == Condition::kDuration
                        ? board_->now - since_ >= task.duration_s
                        : ConditionHolds(task.done_when, -1);
  if (done) {
    report_(GraspEvent::TaskDone, {});
  } else if (board_->now - since_ > task.timeout_s) {
    report_(GraspEvent::TaskFailed, {"task '" + task.name + "' did not finish within " +
                                     std::to_string(task.timeout_s) + " s"});
  }
}

bool LocalTask::InState(const FIstate& state, int finger, Role role) const {
  const bool touching = board_->view.fingers[finger].in_contact;
  if ((state.contact == ContactState::kTouching && !touching) ||
      (state.contact == ContactState::kFree && touching)) {
    return false;
  }
  return !state.role || *state.role == role;
}

bool LocalTask::ConditionHolds(Condition c, int finger) const {
  switch (c) {
    case Condition::kNone: return false;
    case Condition::kContact: return finger >= 0 && board_->view.fingers[finger].in_contact;
    case Condition::kTargetReached: return finger >= 0 && board_->reached[finger];
    case Condition::kGraspStable: return board_->view.grasp_stable;
    case Condition::kMotionDone: return board_->MotionDone();
    case Condition::kDuration: return false;  // checked by the caller against its duration
  }
  return false;
}

Eigen::Vector3d LocalTask::Axis(const std::string& name) const {
  if (name == "task") return params_.axis.direction;
  if (name == "y") return Eigen::Vector3d::UnitY();
  if (name == "z") return Eigen::Vector3d::UnitZ();
  return Eigen::Vector3d::UnitX();
}

}  // namespace dmpl
