#include "supervisor/supervisor.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "components/runtime/check.h"

namespace dmpl {

const char* ToString(GraspState s) {
  switch (s) {
    case GraspState::ObjectHeld: return "ObjectHeld";
    case GraspState::Approaching: return "Approaching";
    case GraspState::Gripping: return "Gripping";
    case GraspState::Releasing: return "Releasing";
    case GraspState::Settling: return "Settling";
    case GraspState::Tasks: return "Tasks";
    case GraspState::Recovering: return "Recovering";
    case GraspState::Holding: return "Holding";
    case GraspState::Done: return "Done";
    case GraspState::Failed: return "Failed";
  }
  return "?";
}

const char* ToString(GraspEvent e) {
  switch (e) {
    case GraspEvent::Start: return "Start";
    case GraspEvent::AllTouching: return "AllTouching";
    case GraspEvent::GraspStable: return "GraspStable";
    case GraspEvent::ReleaseDue: return "ReleaseDue";
    case GraspEvent::Settled: return "Settled";
    case GraspEvent::TaskDone: return "TaskDone";
    case GraspEvent::TaskFailed: return "TaskFailed";
    case GraspEvent::ContactLost: return "ContactLost";
    case GraspEvent::Slip: return "Slip";
    case GraspEvent::Recovered: return "Recovered";
    case GraspEvent::ProcessLost: return "ProcessLost";
    case GraspEvent::ProcessBack: return "ProcessBack";
    case GraspEvent::GraspLost: return "GraspLost";
    case GraspEvent::Timeout: return "Timeout";
  }
  return "?";
}

Supervisor::Supervisor(std::vector<std::string> fingers, TaskFile tasks, TaskParams task_params,
                       SupervisorParams params, uint64_t seed)
    : seed_(seed),
      fingers_(std::move(fingers)),
      tasks_(std::move(tasks)),
      task_params_(std::move(task_params)),
      params_(std::move(params)),
      extensions_(fingers_.size(), 0),
      touched_(fingers_.size(), false),
      reached_(fingers_.size(), false),
      ptask_index_(fingers_.size(), 0),
      ptask_since_(fingers_.size(), 0.0),
      home_(fingers_.size(), Eigen::Vector3d::Zero()),
      replace_(fingers_.size(), Replace::kNone),
      replace_since_(fingers_.size(), 0.0),
      regrasp_(this, fingers_, tasks_.gait.order, task_params_.turn.mode,
               task_params_.grip_while_turning),
      grasp_(BuildGraspChart()) {
  DMPL_DEMAND(fingers_.size() == RegraspChart::kFingers);  // the node's Load says it clearly
  out_.task.fingers.resize(fingers_.size());
  out_.task.name = "idle";
  auto log = [this](const std::string& chart, const auto& t) {
    if (t.row == nullptr) {
      transitions_.push_back(chart + ": " + ToString(t.from) + " ignores " + ToString(t.event));
      return;
    }
    std::string line = chart + ": " + ToString(t.from) + " --" + ToString(t.event);
    if (!t.row->guard.name.empty()) line += " [" + t.row->guard.name + "]";
    if (!t.row->action.name.empty()) line += " / " + t.row->action.name;
    transitions_.push_back(line + "--> " + ToString(t.row->to));
    out_.changed = true;
  };
  grasp_.set_log([this, log](const std::string& chart, const GraspChart::Transition& t) {
    if (t.row != nullptr && t.row->to != t.from) state_since_ = now_;  // timeouts count from here
    log(chart, t);
  });
  regrasp_.set_log(log);
}

// --- commands ------------------------------------------------------------------------------------

void Supervisor::NewTask(const std::string& name) {
  out_.task.task_id = next_task_id_++;
  out_.task.name = name;
  out_.changed = true;
}

int Supervisor::Finger(const std::string& name) const {
  const auto it = std::find(fingers_.begin(), fingers_.end(), name);
  DMPL_DEMAND(it != fingers_.end());
  return static_cast<int>(it - fingers_.begin());
}

void Supervisor::SetFinger(int f, Role role, Primitive primitive, const Eigen::Vector3d* target,
                           double force) {
  FingerTask& t = out_.task.fingers[f];
  t.role = role;
  t.primitive = primitive;
  t.has_target = target != nullptr;
  t.target = target ? *target : Eigen::Vector3d::Zero();
  t.force_n = force;
}

void Supervisor::AllGrip() {
  for (size_t f = 0; f < fingers_.size(); ++f) {
    SetFinger(static_cast<int>(f), Role::kGrip, Primitive::kComposite);
  }
}

void Supervisor::HoldObjectWhereItIs() {
  // The remaining commanded rotation that did not happen is taken back from the account.
  if (has_goal_) {
    const Eigen::AngleAxisd diff(goal_.linear() * view_.object.linear().transpose());
    rotation_commanded_ -= diff.angle() * diff.axis().dot(Axis("task"));
  }
  goal_ = view_.object;
  has_goal_ = true;
  out_.task.has_object_target = true;
  out_.task.object_target = goal_;
}

Eigen::Vector3d Supervisor::Axis(const std::string& name) const {
  if (name == "task") return task_params_.axis.direction;
  if (name == "y") return Eigen::Vector3d::UnitY();
  if (name == "z") return Eigen::Vector3d::UnitZ();
  return Eigen::Vector3d::UnitX();
}

Eigen::Quaterniond Supervisor::SensedOrientation() const {
  return Eigen::Quaterniond(view_.object.linear()).normalized();
}

void Supervisor::Note(const std::string& text) {
  note_ = text;
  out_.changed = true;
}

void Supervisor::StartTask(int index) {
  task_index_ = index;
  task_since_ = now_;
  const CTask& task = tasks_.tasks[index];
  NewTask(task.name);
  rotation_at_task_start_ = rotation_commanded_;
  motion_done_event_ = false;
  std::fill(ptask_index_.begin(), ptask_index_.end(), 0);
  std::fill(ptask_since_.begin(), ptask_since_.end(), now_);
  if (task.type == TaskType::kGait) {
    AllGrip();
    rotation_goal_ = rotation_commanded_ + task_params_.angle;
    if (task_params_.has_goals()) StartGoals();
    gait_done_ = false;
    explorer_ = -1;
    phase_since_ = now_;
    regrasp_.Process(RegraspEvent::Begin);
    return;
  }
  // A local task: each finger's first PTask, and the object motion.
  for (size_t f = 0; f < fingers_.size(); ++f) {
    auto it = task.fingers.find(fingers_[f]);
    if (it == task.fingers.end()) it = task.fingers.find("all");
    if (it == task.fingers.end()) {
      SetFinger(static_cast<int>(f), Role::kGrip, Primitive::kComposite);
      continue;
    }
    const PTask& p = it->second.front();
    if (!InState(p.entry, static_cast<int>(f), out_.task.fingers[f].role)) {
      Note("task '" + task.name + "': finger " + fingers_[f] + " is not in its entry state");
    }
    const double force = p.role == Role::kExplore && p.force_n <= 0 ? task_params_.explore_force_n
                                                                    : p.force_n;
    SetFinger(static_cast<int>(f), p.role, p.primitive, p.has_target ? &p.target : nullptr, force);
  }
  if (task.motion) {
    const ObjectMotion& m = *task.motion;
    if (m.reference == ObjectMotion::Reference::kStart) {
      const Eigen::AngleAxisd back(start_pose_.linear() * goal_.linear().transpose());
      RotateGoal(back.axis(), back.angle());
      goal_ = start_pose_;
      out_.task.object_target = goal_;
    } else {
      const double angle = m.angle * (m.angle_in_task_units ? task_params_.angle : 1.0);
      RotateGoal(Axis(m.axis), angle);
    }
    if (m.max_angular_speed > 0) out_.task.max_angular_speed = m.max_angular_speed;
    rotation_goal_ = rotation_commanded_;
    const bool all_grip = std::all_of(out_.task.fingers.begin(), out_.task.fingers.end(),
                                      [](const FingerTask& t) { return t.role == Role::kGrip; });
    if (all_grip) regrasp_.Process(RegraspEvent::LocalRotate);  // A1 TFMR rotate
  } else {
    out_.task.has_object_target = has_goal_;
    out_.task.object_target = goal_;
  }
}

void Supervisor::SetProcessLost(bool lost, const std::string& who) {
  if (lost == process_lost_) return;
  process_lost_ = lost;
  if (lost) {
    grasp_.Process(GraspEvent::ProcessLost, {"process '" + who + "' stopped beating"});
  } else {
    grasp_.Process(GraspEvent::ProcessBack, {"process '" + who + "' is back"});
  }
}

// --- per tick --------------------------------------------------------------------------------

std::string Supervisor::task_name() const {
  return task_index_ >= 0 && task_index_ < num_tasks() ? tasks_.tasks[task_index_].name : "";
}

std::vector<Role> Supervisor::roles() const {
  std::vector<Role> r;
  for (const auto& f : out_.task.fingers) r.push_back(f.role);
  return r;
}

const SupervisorOutput& Supervisor::Step(const ControllerView& view) {
  DMPL_DEMAND(view.fingers.size() == fingers_.size());
  view_ = view;
  AdvanceClock(view.time_s);
  out_.sim = SimRequest::kNone;
  out_.changed = false;
  const GraspState before = grasp_.state();
  if (grasp_.is(GraspState::ObjectHeld)) grasp_.Process(GraspEvent::Start);
  OnControllerEvents(view.events);
  TickGraspChart();
  if (grasp_.state() != before) out_.changed = true;
  if (out_.changed) last_action_ = regrasp_.last_action();
  return out_;
}

// A gap in the sensed clock between two reports (real time: a process of the sensing path
// restarting) is time the loop was blind and the hand held its last command. The supervisor's
// clock does not count it: a phase, a recovery or a goal is not timed out by time it could not
// act in, and on return the task goes on where it was.
void Supervisor::AdvanceClock(double sensed_s) {
  if (last_sensed_s_ >= 0 && sensed_s - last_sensed_s_ > params_.sensing_gap_s) {
    const double gap = sensed_s - last_sensed_s_;
    unseen_s_ += gap;
    Note("the senses were gone for " + std::to_string(gap) + " s; the task goes on");
  }
  last_sensed_s_ = sensed_s;
  now_ = sensed_s - unseen_s_;
}

// Controller events -> chart events.
void Supervisor::OnControllerEvents(const std::vector<ControllerEvent>& events) {
  for (const ControllerEvent& e : events) {
    switch (e.type) {
      case EventType::kTargetReached:
        if (e.finger >= 0) reached_[e.finger] = true;
        break;
      case EventType::kMotionDone:
        motion_done_event_ = true;
        break;
      case EventType::kContactLost:
        if (e.finger >= 0 && out_.task.fingers[e.finger].role == Role::kGrip &&
            grasp_.is(GraspState::Tasks)) {
          grasp_.Process(GraspEvent::ContactLost,
                         {"finger " + fingers_[e.finger] + " lost its grip contact", e.finger});
        }
        break;
      case EventType::kTrackingError:
        if (grasp_.is(GraspState::Tasks)) {
          grasp_.Process(GraspEvent::Slip, {"the object slipped (" + e.text + ")"});
        }
        break;
      case EventType::kGraspLost:
        if (release_sent_) {
          grasp_.Process(GraspEvent::GraspLost, {"the object is lost: " + e.text});
        }
        break;
      default:
        break;
    }
  }
}

// What the grasp chart's state does each tick (timeouts count from entering it).
void Supervisor::TickGraspChart() {
  switch (grasp_.state()) {
    case GraspState::Approaching:
      TickApproach();
      if (now_ - state_since_ > tasks_.grasp.timeout_s && grasp_.is(GraspState::Approaching)) {
        grasp_.Process(GraspEvent::Timeout, {"the fingers did not all touch within " +
                                             std::to_string(tasks_.grasp.timeout_s) + " s"});
      }
      break;
    case GraspState::Gripping:
      if (view_.grasp_stable) {
        grasp_.Process(GraspEvent::GraspStable);
      } else if (now_ - state_since_ > tasks_.grasp.timeout_s) {
        grasp_.Process(GraspEvent::Timeout, {"no stable grasp within " +
                                             std::to_string(tasks_.grasp.timeout_s) + " s"});
      }
      break;
    case GraspState::Releasing:
      if (now_ - stable_at_ >= tasks_.grasp.release_after_stable_s) {
        grasp_.Process(GraspEvent::ReleaseDue);
      }
      break;
    case GraspState::Settling:
      if (now_ - state_since_ >= tasks_.grasp.settle_s) grasp_.Process(GraspEvent::Settled);
      break;
    case GraspState::Tasks:
      if (tasks_.tasks[task_index_].type == TaskType::kGait) {
        TickGait();
      } else {
        TickLocalTask();
      }
      break;
    case GraspState::Recovering:
      TickRecovery();
      break;
    case GraspState::Done:
    case GraspState::Failed:
      if (!stop_sent_ && now_ - state_since_ >= params_.stop_after_s) {
        out_.sim = SimRequest::kStop;
        stop_sent_ = true;
      }
      break;
    default:
      break;
  }
}

void Supervisor::TickRecovery() {
  TickReplace();
  bool all_touch = true;
  for (const auto& f : view_.fingers) all_touch = all_touch && f.in_contact;
  const bool placing = std::any_of(replace_.begin(), replace_.end(),
                                   [](Replace r) { return r != Replace::kNone; });
  if (view_.grasp_stable && all_touch && !placing && now_ - state_since_ > 0.1) {
    grasp_.Process(GraspEvent::Recovered);
  } else if (now_ - state_since_ > params_.recovery_timeout_s) {
    grasp_.Process(GraspEvent::Timeout, {"no stable grasp within the recovery timeout"});
  }
}

}  // namespace dmpl
