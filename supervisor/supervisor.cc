#include "supervisor/supervisor.h"

#include <algorithm>
#include <cmath>

#include "components/runtime/check.h"
#include "supervisor/face_surface.h"
#include "supervisor/gait_geometry.h"

namespace dmpl {

Supervisor::Supervisor(std::vector<std::string> fingers, TaskFile tasks, TaskParams task_params,
                       SupervisorParams params, uint64_t seed,
                       std::shared_ptr<const ContactChooser> chooser)
    : chooser_(std::move(chooser)),
      tasks_(std::move(tasks)),
      task_params_(std::move(task_params)),
      params_(std::move(params)),
      board_(std::move(fingers)),
      clock_(params_.sensing_gap_s),
      goal_(&board_, task_params_.axis.direction),
      gait_(&board_, &goal_, tasks_.gait, task_params_, seed,
            [this](GaitReport r, const std::string& why) { OnGaitReport(r, why); },
            chooser_.get()),
      local_(&board_, &goal_, task_params_,
             [this](GraspEvent e, const GraspEventData& d) { grasp_.Process(e, d); },
             [this] { gait_.LocalRotate(); }),
      replacer_(&board_, params_, chooser_.get(), tasks_.gait.tip_clearance_m),
      extensions_(board_.fingers.size(), 0),
      grasp_(BuildGraspChart()) {
  DMPL_DEMAND(board_.fingers.size() == RegraspChart::kFingers);  // the node's Load says it clearly
  LogTransitions();
}

void Supervisor::LogTransitions() {
  auto log = [this](const std::string& chart, const auto& t) {
    if (t.row == nullptr) {
      transitions_.push_back(chart + ": " + ToString(t.from) + " ignores " + ToString(t.event));
      return;
    }
    std::string line = chart + ": " + ToString(t.from) + " --" + ToString(t.event);
    if (!t.row->guard.name.empty()) line += " [" + t.row->guard.name + "]";
    if (!t.row->action.name.empty()) line += " / " + t.row->action.name;
    transitions_.push_back(line + "--> " + ToString(t.row->to));
    board_.out.changed = true;
  };
  grasp_.set_log([this, log](const std::string& chart, const GraspChart::Transition& t) {
    if (t.row != nullptr && t.row->to != t.from) state_since_ = board_.now;  // timeouts from here
    log(chart, t);
  });
  gait_.set_log(log);
}

std::string Supervisor::task_name() const {
  return task_index_ >= 0 && task_index_ < num_tasks() ? task().name : "";
}

std::vector<Role> Supervisor::roles() const {
  std::vector<Role> r;
  for (const auto& f : board_.out.task.fingers) r.push_back(f.role);
  return r;
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

const SupervisorOutput& Supervisor::Step(const ControllerView& view) {
  DMPL_DEMAND(view.fingers.size() == board_.fingers.size());
  board_.view = view;
  board_.out.sim = SimRequest::kNone;
  board_.out.changed = false;
  AdvanceClock(view.time_s);
  board_.LearnSurface();
  const GraspState before = grasp_.state();
  if (grasp_.is(GraspState::ObjectHeld)) grasp_.Process(GraspEvent::Start);
  OnControllerEvents(view.events);
  TickGraspChart();
  AskFacing();
  if (grasp_.state() != before) board_.out.changed = true;
  if (board_.out.changed) last_action_ = gait_.chart().last_action();
  return board_.out;
}

// A gap in the sensed clock between two reports (real time: a process of the sensing path
// restarting) is time the loop was blind and the hand held its last command. The supervisor's
// clock does not count it: a phase, a recovery or a goal is not timed out by time it could not
// act in, and on return the task goes on where it was.
void Supervisor::AdvanceClock(double sensed_s) {
  const double gap = clock_.Advance(sensed_s).gap_s;
  board_.now = clock_.now();
  // Once the tasks have ended the note says why (the simulator's STOP carries it).
  const bool ended = grasp_.is(GraspState::Done) || grasp_.is(GraspState::Failed);
  if (gap > 0 && !ended) {
    board_.Note("the senses were gone for " + std::to_string(gap) + " s; going on");
  }
}

// Controller events -> chart events.
void Supervisor::OnControllerEvents(const std::vector<ControllerEvent>& events) {
  for (const ControllerEvent& e : events) {
    switch (e.type) {
      case EventType::kTargetReached:
        if (e.finger >= 0) board_.reached[e.finger] = true;
        break;
      case EventType::kMotionDone:
        board_.motion_done_event = true;
        break;
      case EventType::kLinkContact:
        if (e.finger >= 0) {
          if (!board_.on_link[e.finger]) board_.on_link_since[e.finger] = board_.now;
          board_.link_touched[e.finger] = board_.on_link[e.finger] = true;
        }
        break;
      case EventType::kLinkReleased:
        if (e.finger >= 0) board_.on_link[e.finger] = false;
        break;
      case EventType::kContactLost:
        if (e.finger >= 0 && board_.out.task.fingers[e.finger].role == Role::kGrip &&
            grasp_.is(GraspState::Tasks)) {
          grasp_.Process(GraspEvent::ContactLost, {"finger " + board_.fingers[e.finger] +
                                                       " lost its grip contact", e.finger});
        }
        break;
      case EventType::kSinking: {
        const int explorer = board_.Explorer();
        if (params_.catch_sinking && grasp_.is(GraspState::Tasks) && explorer >= 0 &&
            // Over the palm: gravity within 45 deg of pointing into it.
            GaitGeometry::PalmBelow(board_.view.gravity, std::cos(M_PI / 4))) {
          grasp_.Process(GraspEvent::Slip, {"the object sinks out of the grip while " +
                                                board_.fingers[explorer] + " explores (" +
                                                e.text + ")"});
        }
        break;
      }
      case EventType::kTrackingError:
        if (grasp_.is(GraspState::Tasks)) {
          grasp_.Process(GraspEvent::Slip, {"the object slipped (" + e.text + ")"});
        }
        break;
      case EventType::kGraspLost:
        if (release_sent_) grasp_.Process(GraspEvent::GraspLost, {"the object is lost: " + e.text});
        break;
      default:
        break;
    }
  }
}

void Supervisor::OnGaitReport(GaitReport report, const std::string& reason) {
  switch (report) {
    case GaitReport::kGoalReached: recoveries_counted_ = 0; break;
    case GaitReport::kDone: grasp_.Process(GraspEvent::TaskDone); break;
    case GaitReport::kFailed: grasp_.Process(GraspEvent::TaskFailed, {reason}); break;
    case GaitReport::kSlipped: grasp_.Process(GraspEvent::Slip, {reason}); break;
  }
}

bool Supervisor::InState(GraspState s, double longer_than_s) const {
  return grasp_.is(s) && board_.now - state_since_ > longer_than_s;
}

// What the grasp chart's state does each tick (timeouts count from entering it).
void Supervisor::TickGraspChart() {
  const double now = board_.now;
  const GraspSpec& g = tasks_.grasp;
  switch (grasp_.state()) {
    case GraspState::Approaching:
      TickApproach();
      break;
    case GraspState::Gripping:
      if (board_.view.grasp_stable) {
        grasp_.Process(GraspEvent::GraspStable);
      } else if (InState(GraspState::Gripping, g.timeout_s)) {
        grasp_.Process(GraspEvent::Timeout,
                       {"no stable grasp within " + std::to_string(g.timeout_s) + " s"});
      }
      break;
    case GraspState::Releasing:
      if (now - stable_at_ >= g.release_after_stable_s) grasp_.Process(GraspEvent::ReleaseDue);
      break;
    case GraspState::Settling:
      if (now - state_since_ >= g.settle_s) grasp_.Process(GraspEvent::Settled);
      break;
    case GraspState::Tasks:
      if (CheckLinkRest()) break;
      GaitUnderWay() ? gait_.Tick() : local_.Tick(task());
      break;
    case GraspState::Recovering:
      TickRecovery();
      break;
    case GraspState::Done:
    case GraspState::Failed:
      TickEnded();
      break;
    default:
      break;
  }
}

// After the last task or a failure: the simulator is stopped a moment later.
// The STOP rides with the joint commands planned from its task: in real time a process of that
// path restarting (or a lost message) can lose it, and the simulator would run on to its time
// limit. While reports keep coming, the simulator has not stopped: the STOP goes again every
// stop_after_s of sensed time.
void Supervisor::TickEnded() {
  const double since = stop_sent_ ? stop_sent_at_ : state_since_;
  if (board_.now - since >= params_.stop_after_s) {
    board_.out.sim = SimRequest::kStop;
    stop_sent_ = true;
    stop_sent_at_ = board_.now;
  }
}

void Supervisor::TickRecovery() {
  if (task_index_ >= 0) replacer_.Tick(state_since_);
  const auto& fingers = board_.view.fingers;
  const bool all_touch = std::all_of(fingers.begin(), fingers.end(),
                                     [](const FingerView& f) { return f.in_contact; });
  if (board_.view.grasp_stable && all_touch && !replacer_.placing() &&
      InState(GraspState::Recovering, 0.1)) {
    grasp_.Process(GraspEvent::Recovered);
  } else if (InState(GraspState::Recovering, params_.recovery_timeout_s)) {
    grasp_.Process(GraspEvent::Timeout, {"no stable grasp within the recovery timeout"});
  }
}

// A grip finger resting on a link (FingerReplacer::RestsOnLink): its force loop pushes the object
// through the link, and a step it rides does not finish. The recovery lifts it and places it
// again on its tip.
bool Supervisor::CheckLinkRest() {
  for (int f = 0; f < board_.num_fingers(); ++f) {
    // A rest counts from when the finger grips: an explorer's link brushing the object is not one.
    if (board_.out.task.fingers[f].role != Role::kGrip) board_.on_link_since[f] = board_.now;
    if (replacer_.RestsOnLink(f)) {
      grasp_.Process(GraspEvent::LinkRest,
                     {"finger " + board_.fingers[f] + " rests on a link", f});
      return true;
    }
  }
  return false;
}

void Supervisor::AskFacing() {
  if (!task_params_.face_surface.enabled || chooser_ == nullptr || board_.tip_radius_m <= 0 ||
      board_.out.task.task_id == facing_task_id_) {
    return;
  }
  facing_task_id_ = board_.out.task.task_id;
  AskToFaceSurface(*chooser_, task_params_.face_surface, board_.view, board_.surface,
                   board_.flat_faces, board_.tip_radius_m, &board_.out.task);
}

bool Supervisor::GaitUnderWay() const {
  return task_index_ >= 0 && task().type == TaskType::kGait;
}

}  // namespace dmpl
