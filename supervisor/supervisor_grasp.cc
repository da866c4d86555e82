// The grasp chart (the paper's Fig. 5) and its actions: approach, grip, release, the tasks,
// recover, hold, fail.
#include <string>

#include "supervisor/supervisor.h"

namespace dmpl {

struct Supervisor::GraspChartActions {
  GraspChart::Action approach, grip, schedule_release, release, first_task, next_task, finish,
      regrip, resume, hold, fail;
  sc::Guard more, last, can_recover, cannot_recover;
};

Supervisor::GraspChartActions Supervisor::MakeGraspChartActions() {
  using Action = GraspChart::Action;
  using WithData = std::function<void(const GraspEventData&)>;
  using Plain = std::function<void()>;
  return {
      Action("approach the contact points", Plain([this] { Approach(); })),
      Action("composite grip", Plain([this] { board_.NewTask("grip"), board_.AllGrip(); })),
      Action("wait, then release", Plain([this] { stable_at_ = board_.now; })),
      Action("release the object", Plain([this] {
               board_.out.sim = SimRequest::kRelease;
               release_sent_ = true;
             })),
      Action("start the first task", Plain([this] { BeginTasks(); })),
      Action("start the next task", Plain([this] { StartTask(task_index_ + 1); })),
      Action("all tasks done", Plain([this] { Finish(); })),
      Action("pause and re-grip", WithData([this](const GraspEventData& e) {
               PauseAndRegrip(e.reason);
             })),
      Action("resume the task", Plain([this] { Resume(); })),
      Action("hold the grasp", WithData([this](const GraspEventData& e) { Hold(e.reason); })),
      Action("fail", WithData([this](const GraspEventData& e) { Fail(e.reason); })),
      sc::Guard("more tasks", [this] { return task_index_ + 1 < num_tasks(); }),
      sc::Guard("last task", [this] { return task_index_ + 1 >= num_tasks(); }),
      sc::Guard("recoveries left", [this] { return recoveries_counted_ < params_.max_recoveries; }),
      sc::Guard("no recoveries left",
                [this] { return recoveries_counted_ >= params_.max_recoveries; }),
  };
}

Supervisor::GraspChart Supervisor::BuildGraspChart() {
  using S = GraspState;
  using E = GraspEvent;
  const GraspChartActions a = MakeGraspChartActions();
  return GraspChart("grasp", S::ObjectHeld, {
      // from           event             guard             action              to
      {S::ObjectHeld,  E::Start,         sc::kAlways,      a.approach,         S::Approaching},
      {S::Approaching, E::AllTouching,   sc::kAlways,      a.grip,             S::Gripping},
      {S::Approaching, E::Timeout,       sc::kAlways,      a.fail,             S::Failed},
      {S::Gripping,    E::GraspStable,   sc::kAlways,      a.schedule_release, S::Releasing},
      {S::Gripping,    E::Timeout,       sc::kAlways,      a.fail,             S::Failed},
      {S::Releasing,   E::ReleaseDue,    sc::kAlways,      a.release,          S::Settling},
      {S::Settling,    E::Settled,       sc::kAlways,      a.first_task,       S::Tasks},
      {S::Settling,    E::GraspLost,     sc::kAlways,      a.fail,             S::Failed},
      {S::Tasks,       E::TaskDone,      a.more,           a.next_task,        S::Tasks},
      {S::Tasks,       E::TaskDone,      a.last,           a.finish,           S::Done},
      {S::Tasks,       E::TaskFailed,    sc::kAlways,      a.fail,             S::Failed},
      {S::Tasks,       E::ContactLost,   a.can_recover,    a.regrip,           S::Recovering},
      {S::Tasks,       E::Slip,          a.can_recover,    a.regrip,           S::Recovering},
      {S::Tasks,       E::ContactLost,   a.cannot_recover, a.fail,             S::Failed},
      {S::Tasks,       E::LinkRest,      a.can_recover,    a.regrip,           S::Recovering},
      {S::Tasks,       E::LinkRest,      a.cannot_recover, a.fail,             S::Failed},
      {S::Tasks,       E::Slip,          a.cannot_recover, a.fail,             S::Failed},
      {S::Tasks,       E::GraspLost,     sc::kAlways,      a.fail,             S::Failed},
      {S::Recovering,  E::Recovered,     sc::kAlways,      a.resume,           S::Tasks},
      {S::Recovering,  E::Timeout,       sc::kAlways,      a.fail,             S::Failed},
      {S::Recovering,  E::GraspLost,     sc::kAlways,      a.fail,             S::Failed},
      {S::Settling,    E::ProcessLost,   sc::kAlways,      a.hold,             S::Holding},
      {S::Tasks,       E::ProcessLost,   sc::kAlways,      a.hold,             S::Holding},
      {S::Recovering,  E::ProcessLost,   sc::kAlways,      a.hold,             S::Holding},
      {S::Holding,     E::ProcessBack,   sc::kAlways,      a.regrip,           S::Recovering},
      {S::Holding,     E::GraspLost,     sc::kAlways,      a.fail,             S::Failed},
      {S::Done,        E::GraspLost,     sc::kAlways,      a.fail,             S::Failed},
  });
}

void Supervisor::Approach() {
  board_.NewTask("approach");
  for (int f = 0; f < board_.num_fingers(); ++f) {
    const auto it = tasks_.grasp.approach.find(board_.fingers[f]);
    if (it == tasks_.grasp.approach.end()) {
      // No approach points: the fingers already touch; grip in place.
      board_.SetFinger(f, Role::kGrip, Primitive::kComposite);
    } else {
      const Eigen::Vector3d point(it->second[0], it->second[1], it->second[2]);
      board_.SetFinger(f, Role::kFree, Primitive::kPosition, &point);
    }
  }
}

void Supervisor::TickApproach() {
  bool all = true;
  for (int f = 0; f < board_.num_fingers(); ++f) {
    const bool touching = board_.view.fingers[f].in_contact;
    if (board_.out.task.fingers[f].primitive == Primitive::kPosition) {
      if (touching) {
        // Tactile contact: from position to composite control (Fig. 5).
        board_.SetFinger(f, Role::kGrip, Primitive::kComposite);
        board_.out.changed = true;
      } else if (board_.reached[f]) {
        ReachFurther(f);
        if (!grasp_.is(GraspState::Approaching)) return;
      }
    }
    all = all && board_.out.task.fingers[f].primitive == Primitive::kComposite && touching;
  }
  if (all) grasp_.Process(GraspEvent::AllTouching);
  if (InState(GraspState::Approaching, tasks_.grasp.timeout_s)) {
    grasp_.Process(GraspEvent::Timeout, {"the fingers did not all touch within " +
                                         std::to_string(tasks_.grasp.timeout_s) + " s"});
  }
}

// At the point and still nothing: the object is smaller; reach further in.
void Supervisor::ReachFurther(int f) {
  board_.reached[f] = false;
  if (++extensions_[f] > tasks_.grasp.max_extensions) {
    grasp_.Process(GraspEvent::Timeout, {"finger " + board_.fingers[f] + " found no object"});
    return;
  }
  const Eigen::Vector3d& target = board_.out.task.fingers[f].target;
  const Eigen::Vector3d in = (board_.view.object.translation() - target).normalized();
  const Eigen::Vector3d further = target + tasks_.grasp.approach_extension_m * in;
  board_.SetFinger(f, Role::kFree, Primitive::kPosition, &further);
  board_.out.changed = true;
}

// The first task begins: where the object and each fingertip are is the start and the homes.
void Supervisor::BeginTasks() {
  goal_.Begin(board_.view.object);
  for (int f = 0; f < board_.num_fingers(); ++f) board_.home[f] = board_.view.fingers[f].tip;
  board_.home_centre = board_.view.object.translation();
  StartTask(0);
}

void Supervisor::StartTask(int index) {
  task_index_ = index;
  local_.Start(task(), gait_.StepSpeed());
  if (task().type == TaskType::kGait) gait_.Start();
}

void Supervisor::Finish() {
  board_.NewTask("done");
  board_.AllGrip();
  goal_.HoldWhereItIs();
}

void Supervisor::PauseAndRegrip(const std::string& why) {
  ++recoveries_;
  ++recoveries_counted_;
  if (GaitUnderWay()) gait_.Abort();
  board_.NewTask("recover");
  board_.AllGrip();
  replacer_.Reset();
  // The orientation where the object is (what turned, turned), the position where the task held
  // it: an object that drifted away from a finger that lost it is brought back into that
  // finger's reach instead of being held where the finger cannot touch it.
  goal_.HoldTurnedWhereItIs();
  board_.Note("recovering: " + why);
}

void Supervisor::Resume() {
  board_.Note("resumed after " + std::to_string(recoveries_) + " recoveries");
  if (!GaitUnderWay()) {
    local_.Resume(task(), gait_.StepSpeed());
    return;
  }
  board_.NewTask(task().name);
  board_.AllGrip();
  gait_.Resume();
}

void Supervisor::Hold(const std::string& why) {
  if (GaitUnderWay()) gait_.Abort();
  board_.NewTask("hold");
  board_.AllGrip();
  goal_.HoldWhereItIs();
  board_.Note("holding the grasp: " + why);
}

void Supervisor::Fail(const std::string& why) {
  board_.NewTask("failed");
  board_.AllGrip();
  goal_.HoldWhereItIs();
  board_.Note("failed: " + why);
}

}  // namespace dmpl
