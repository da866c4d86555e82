// The grasp chart (the paper's Fig. 5) and its actions: approach, grip, release, recover, hold,
// fail.
#include "supervisor/supervisor.h"

#include <algorithm>
#include <string>

#include "components/runtime/check.h"

namespace dmpl {

Supervisor::GraspChart Supervisor::BuildGraspChart() {
  using S = GraspState;
  using E = GraspEvent;
  using Action = GraspChart::Action;
  const Action approach("approach the contact points", [this] { Approach(); });
  const Action grip("composite grip", [this] {
    NewTask("grip");
    AllGrip();
  });
  const Action schedule_release("wait, then release", [this] { stable_at_ = now_; });
  const Action release("release the object", [this] {
    out_.sim = SimRequest::kRelease;
    release_sent_ = true;
  });
  const Action first_task("start the first task", [this] {
    start_pose_ = view_.object;
    goal_ = view_.object;
    has_goal_ = true;
    for (size_t f = 0; f < fingers_.size(); ++f) home_[f] = view_.fingers[f].tip;
    home_centre_ = view_.object.translation();
    StartTask(0);
  });
  const Action next_task("start the next task", [this] { StartTask(task_index_ + 1); });
  const Action finish("all tasks done", [this] {
    NewTask("done");
    AllGrip();
    HoldObjectWhereItIs();
  });
  const Action regrip("pause and re-grip",
                      [this](const GraspEventData& e) { PauseAndRegrip(e.reason); });
  const Action resume("resume the task", [this] { Resume(); });
  const Action hold("hold the grasp", [this](const GraspEventData& e) { Hold(e.reason); });
  const Action fail("fail", [this](const GraspEventData& e) { Fail(e.reason); });
  const sc::Guard more("more tasks", [this] { return task_index_ + 1 < num_tasks(); });
  const sc::Guard last("last task", [this] { return task_index_ + 1 >= num_tasks(); });
  const sc::Guard can_recover("recoveries left",
                              [this] { return recoveries_counted_ < params_.max_recoveries; });
  const sc::Guard cannot_recover("no recoveries left",
                                 [this] { return recoveries_counted_ >= params_.max_recoveries; });
  return GraspChart("grasp", S::ObjectHeld, {
      // from           event             guard           action            to
      {S::ObjectHeld,  E::Start,         sc::kAlways,    approach,         S::Approaching},
      {S::Approaching, E::AllTouching,   sc::kAlways,    grip,             S::Gripping},
      {S::Approaching, E::Timeout,       sc::kAlways,    fail,             S::Failed},
      {S::Gripping,    E::GraspStable,   sc::kAlways,    schedule_release, S::Releasing},
      {S::Gripping,    E::Timeout,       sc::kAlways,    fail,             S::Failed},
      {S::Releasing,   E::ReleaseDue,    sc::kAlways,    release,          S::Settling},
      {S::Settling,    E::Settled,       sc::kAlways,    first_task,       S::Tasks},
      {S::Settling,    E::GraspLost,     sc::kAlways,    fail,             S::Failed},
      {S::Tasks,       E::TaskDone,      more,           next_task,        S::Tasks},
      {S::Tasks,       E::TaskDone,      last,           finish,           S::Done},
      {S::Tasks,       E::TaskFailed,    sc::kAlways,    fail,             S::Failed},
      {S::Tasks,       E::ContactLost,   can_recover,    regrip,           S::Recovering},
      {S::Tasks,       E::Slip,          can_recover,    regrip,           S::Recovering},
      {S::Tasks,       E::ContactLost,   cannot_recover, fail,             S::Failed},
      {S::Tasks,       E::Slip,          cannot_recover, fail,             S::Failed},
      {S::Tasks,       E::GraspLost,     sc::kAlways,    fail,             S::Failed},
      {S::Recovering,  E::Recovered,     sc::kAlways,    resume,           S::Tasks},
      {S::Recovering,  E::Timeout,       sc::kAlways,    fail,             S::Failed},
      {S::Recovering,  E::GraspLost,     sc::kAlways,    fail,             S::Failed},
      {S::Settling,    E::ProcessLost,   sc::kAlways,    hold,             S::Holding},
      {S::Tasks,       E::ProcessLost,   sc::kAlways,    hold,             S::Holding},
      {S::Recovering,  E::ProcessLost,   sc::kAlways,    hold,             S::Holding},
      {S::Holding,     E::ProcessBack,   sc::kAlways,    regrip,           S::Recovering},
      {S::Holding,     E::GraspLost,     sc::kAlways,    fail,             S::Failed},
      {S::Done,        E::GraspLost,     sc::kAlways,    fail,             S::Failed},
  });
}

void Supervisor::Approach() {
  NewTask("approach");
  for (size_t f = 0; f < fingers_.size(); ++f) {
    const auto it = tasks_.grasp.approach.find(fingers_[f]);
    if (it == tasks_.grasp.approach.end()) {
      // No approach points: the fingers already touch; grip in place.
      SetFinger(static_cast<int>(f), Role::kGrip, Primitive::kComposite);
    } else {
      SetFinger(static_cast<int>(f), Role::kFree, Primitive::kPosition, &it->second);
    }
  }
}

void Supervisor::TickApproach() {
  bool all = true;
  for (size_t f = 0; f < fingers_.size(); ++f) {
    FingerTask& t = out_.task.fingers[f];
    if (t.primitive == Primitive::kPosition) {
      if (view_.fingers[f].in_contact) {
        // Tactile contact: from position to composite control (Fig. 5).
        SetFinger(static_cast<int>(f), Role::kGrip, Primitive::kComposite);
        out_.changed = true;
      } else if (reached_[f]) {
        // At the point and still nothing: the object is smaller; reach further in.
        reached_[f] = false;
        if (++extensions_[f] > tasks_.grasp.max_extensions) {
          grasp_.Process(GraspEvent::Timeout, {"finger " + fingers_[f] + " found no object"});
          return;
        }
        const Eigen::Vector3d in = (view_.object.translation() - t.target).normalized();
        const Eigen::Vector3d further = t.target + tasks_.grasp.approach_extension_m * in;
        SetFinger(static_cast<int>(f), Role::kFree, Primitive::kPosition, &further);
        out_.changed = true;
      }
    }
    all = all && out_.task.fingers[f].primitive == Primitive::kComposite &&
          view_.fingers[f].in_contact;
  }
  if (all) grasp_.Process(GraspEvent::AllTouching);
}

void Supervisor::PauseAndRegrip(const std::string& why) {
  ++recoveries_;
  ++recoveries_counted_;
  if (task_index_ >= 0 && tasks_.tasks[task_index_].type == TaskType::kGait) {
    regrasp_.Process(RegraspEvent::Abort);
    explorer_ = -1;
  }
  NewTask("recover");
  AllGrip();
  std::fill(replace_.begin(), replace_.end(), Replace::kNone);
  // The orientation where the object is (what turned, turned), the position where the task held
  // it: an object that drifted away from a finger that lost it is brought back into that
  // finger's reach instead of being held where the finger cannot touch it.
  const Eigen::Vector3d position = goal_.translation();
  const bool had_goal = has_goal_;
  HoldObjectWhereItIs();
  if (had_goal) {
    goal_.translation() = position;
    out_.task.object_target = goal_;
  }
  Note("recovering: " + why);
}

void Supervisor::Resume() {
  const CTask& task = tasks_.tasks[task_index_];
  Note("resumed after " + std::to_string(recoveries_) + " recoveries");
  if (task.type == TaskType::kGait) {
    NewTask(task.name);
    AllGrip();
    phase_since_ = now_;
    regrasp_.Process(RegraspEvent::Begin);
    return;
  }
  // A local task starts over toward the goal it had; what was already turned counts.
  const double done = rotation_commanded_ - rotation_at_task_start_;
  StartTask(task_index_);
  if (task.motion && task.motion->reference == ObjectMotion::Reference::kCurrent) {
    RotateGoal(Axis(task.motion->axis), -done);
    rotation_goal_ = rotation_commanded_;
  }
}

void Supervisor::Hold(const std::string& why) {
  if (task_index_ >= 0 && tasks_.tasks[task_index_].type == TaskType::kGait) {
    regrasp_.Process(RegraspEvent::Abort);
  }
  NewTask("hold");
  AllGrip();
  HoldObjectWhereItIs();
  Note("holding the grasp: " + why);
}

void Supervisor::Fail(const std::string& why) {
  NewTask("failed");
  AllGrip();
  if (view_.fingers.size() == fingers_.size()) HoldObjectWhereItIs();
  Note("failed: " + why);
}

// A grip finger that does not touch again in a recovery: lifted off, moved over its home, brought
// in by a grip (supervisor.replace_after_s).
void Supervisor::TickReplace() {
  if (params_.replace_after_s <= 0 || task_index_ < 0) return;
  const Eigen::Vector3d centre = view_.object.translation();
  for (size_t k = 0; k < fingers_.size(); ++k) {
    const int f = static_cast<int>(k);
    const double since = now_ - replace_since_[k];
    switch (replace_[k]) {
      case Replace::kNone:
        if (!view_.fingers[k].in_contact && now_ - state_since_ > params_.replace_after_s) {
          // Off the surface along the line from the centre.
          Eigen::Vector3d out = view_.fingers[k].tip - centre;
          if (out.norm() < 1e-6) out = home_[k] - home_centre_;
          const Eigen::Vector3d target =
              view_.fingers[k].tip + params_.replace_lift_m * out.normalized();
          SetFinger(f, Role::kFree, Primitive::kPosition, &target);
          reached_[k] = false;
          replace_[k] = Replace::kLift;
          replace_since_[k] = now_;
          Note("placing finger " + fingers_[k] + " again");
        }
        break;
      case Replace::kLift:
        if (reached_[k] || since > 1.0) {
          // Over its home, as far out.
          const Eigen::Vector3d home = home_[k] - home_centre_;
          const Eigen::Vector3d target =
              centre + home.normalized() * (home.norm() + params_.replace_lift_m);
          SetFinger(f, Role::kFree, Primitive::kPosition, &target);
          reached_[k] = false;
          replace_[k] = Replace::kOver;
          replace_since_[k] = now_;
          out_.changed = true;
        }
        break;
      case Replace::kOver:
        if (reached_[k] || since > 1.5) {
          SetFinger(f, Role::kGrip, Primitive::kComposite);
          replace_[k] = Replace::kIn;
          replace_since_[k] = now_;
          out_.changed = true;
        }
        break;
      case Replace::kIn:
        // Touching: done; still nothing after a while: lift and try again.
        if (view_.fingers[k].in_contact || since > 1.0) replace_[k] = Replace::kNone;
        break;
    }
  }
}

}  // namespace dmpl
