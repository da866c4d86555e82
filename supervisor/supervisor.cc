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

namespace {
std::string Fixed(double value, int digits = 2) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << value;
  return os.str();
}

RegraspChart::Turn TurnOf(const std::string& turn) {
  if (turn == "three") return RegraspChart::Turn::kThreeFingers;
  if (turn == "four") return RegraspChart::Turn::kFourFingers;
  if (turn == "continuous") return RegraspChart::Turn::kContinuous;
  return RegraspChart::Turn::kAuto;
}
}  // namespace

void TaskParams::Validate(const std::string& source) const {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'task." + key + "': " + what);
  };
  if (!std::isfinite(angle)) fail("angle", "must be finite");
  if (!(step > 0) || step > 1.0) fail("step", "must be in (0, 1] rad");
  if (turn != "three" && turn != "four" && turn != "continuous" && turn != "auto") {
    fail("turn", "must be 'auto', 'continuous', 'four' or 'three' (the paper's)");
  }
  if (!(angular_speed > 0)) fail("angular_speed", "must be > 0");
  if (!(overlap_angular_speed >= 0)) fail("overlap_angular_speed", "must be >= 0");
  if (explore_force_n < 0) fail("explore_force_n", "must be >= 0");
  if (explore_travel < 0) fail("explore_travel", "must be >= 0");
  if (random_goals < 0 || random_goals > 100000) fail("random_goals", "must be in [0, 100000]");
  if (!(random_goal_separation_rad >= 0) || random_goal_separation_rad > 3.0) {
    fail("random_goal_separation_rad", "must be in [0, 3] rad (further apart is rare)");
  }
  if (!(goal_tolerance_rad > 0) || goal_tolerance_rad > M_PI) {
    fail("goal_tolerance_rad", "must be in (0, pi]");
  }
  if (!(goal_hold_s >= 0)) fail("goal_hold_s", "must be >= 0");
}

bool TaskParams::has_goals() const { return !goals.empty() || random_goals > 0; }

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
      regrasp_(this, tasks_.gait.order, TurnOf(task_params_.turn)),
      grasp_(BuildGraspChart()) {
  DMPL_DEMAND(fingers_.size() == 4);
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

Supervisor::GraspChart Supervisor::BuildGraspChart() {
  using S = GraspState;
  using E = GraspEvent;
  const sc::Action approach("approach the contact points", [this] { Approach(); });
  const sc::Action grip("composite grip", [this] {
    NewTask("grip");
    AllGrip();
  });
  const sc::Action schedule_release("wait, then release", [this] { stable_at_ = now_; });
  const sc::Action release("release the object", [this] {
    out_.sim = SimRequest::kRelease;
    release_sent_ = true;
  });
  const sc::Action first_task("start the first task", [this] {
    start_pose_ = view_.object;
    goal_ = view_.object;
    has_goal_ = true;
    for (size_t f = 0; f < fingers_.size(); ++f) home_[f] = view_.fingers[f].tip;
    home_centre_ = view_.object.translation();
    StartTask(0);
  });
  const sc::Action next_task("start the next task", [this] { StartTask(task_index_ + 1); });
  const sc::Action finish("all tasks done", [this] {
    NewTask("done");
    AllGrip();
    HoldObjectWhereItIs();
  });
  const sc::Action regrip("pause and re-grip", [this] { PauseAndRegrip(note_); });
  const sc::Action resume("resume the task", [this] { Resume(); });
  const sc::Action hold("hold the grasp", [this] { Hold(note_); });
  const sc::Action fail("fail", [this] { Fail(note_); });
  const sc::Guard more("more tasks", [this] { return task_index_ + 1 < num_tasks(); });
  const sc::Guard last("last task", [this] { return task_index_ + 1 >= num_tasks(); });
  const sc::Guard can_recover("recoveries left",
                              [this] { return recoveries_ < params_.max_recoveries; });
  const sc::Guard cannot_recover("no recoveries left",
                                 [this] { return recoveries_ >= params_.max_recoveries; });
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

void Supervisor::StartGoals() {
  std::vector<Eigen::Quaterniond> goals;
  for (const OrientationParam& g : task_params_.goals) goals.push_back(g.q);
  const Eigen::Quaterniond from = goals.empty() ? SensedOrientation() : goals.back();
  for (const auto& q : RandomGoals(seed_, task_params_.random_goals,
                                   task_params_.random_goal_separation_rad, from)) {
    goals.push_back(q);
  }
  goals_ = GoalSequence(std::move(goals), task_params_.goal_tolerance_rad,
                        task_params_.goal_hold_s, task_params_.goal_timeout_s);
  goals_.Start(now_);
}

void Supervisor::RotateGoal(const Eigen::Vector3d& axis, double angle) {
  goal_.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * goal_.linear();
  has_goal_ = true;
  rotation_commanded_ += angle * axis.dot(Axis("task"));
  out_.task.has_object_target = true;
  out_.task.object_target = goal_;
  out_.task.max_angular_speed = StepSpeed();
  motion_done_event_ = false;
}

double Supervisor::StepSpeed() const {
  const double overlap = task_params_.overlap_angular_speed;
  return regrasp_.exploring() && regrasp_.overlapping() && overlap > 0
             ? overlap
             : task_params_.angular_speed;
}

void Supervisor::Note(const std::string& text) {
  note_ = text;
  out_.changed = true;
}

// --- grasp chart actions ---------------------------------------------------------------------

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

void Supervisor::StartTask(int index) {
  task_index_ = index;
  task_since_ = now_;
  const CTask& task = tasks_.tasks[index];
  NewTask(task.name);
  rotation_at_task_start_ = rotation_commanded_;
  motion_done_event_ = false;
  std::fill(ptask_index_.begin(), ptask_index_.end(), 0);
  std::fill(ptask_since_.begin(), ptask_since_.end(), now_);
  if (task.type == "gait") {
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

void Supervisor::PauseAndRegrip(const std::string& why) {
  ++recoveries_;
  if (task_index_ >= 0 && tasks_.tasks[task_index_].type == "gait") {
    regrasp_.Process(RegraspEvent::Abort);
    explorer_ = -1;
  }
  NewTask("recover");
  AllGrip();
  HoldObjectWhereItIs();
  Note("recovering: " + why);
}

void Supervisor::Resume() {
  const CTask& task = tasks_.tasks[task_index_];
  Note("resumed after " + std::to_string(recoveries_) + " recoveries");
  if (task.type == "gait") {
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
  if (task_index_ >= 0 && tasks_.tasks[task_index_].type == "gait") {
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

// --- regrasp actions -------------------------------------------------------------------------

void Supervisor::Explore(const std::string& finger) {
  const int f = Finger(finger);
  explorer_ = f;
  phase_since_ = now_;
  reached_[f] = false;
  // Back against the rotation to where the finger can follow the steps it turns with until it
  // explores again (all of them, or all but its own): half of them behind its home, half ahead, so
  // it never drifts to its joint limits.
  // Toward a goal orientation the steps turn about the axis to it (positive angles).
  const bool to_goal = task_params_.has_goals();
  const double sign = to_goal || task_params_.angle >= 0 ? 1.0 : -1.0;
  const Eigen::Vector3d axis = StepAxis();
  const double n = static_cast<double>(fingers_.size());
  // With four the explorer rides every step; when the others turn while it slides, all but one.
  const bool four = regrasp_.turn() == RegraspChart::Turn::kFourFingers ||
                    (regrasp_.turn() == RegraspChart::Turn::kAuto && !regrasp_.overlapping());
  const double rides = four ? n : n - 1;
  const double back = -sign * task_params_.explore_travel * rides * task_params_.step / 2.0;
  const Eigen::AngleAxisd turn(back, axis);
  explore_target_ = view_.object.translation() + turn * (home_[f] - home_centre_);
  NewTask(regrasp_.last_action());
  for (size_t k = 0; k < fingers_.size(); ++k) {
    if (static_cast<int>(k) == f) {
      SetFinger(f, Role::kExplore, Primitive::kHybrid, &explore_target_, task_params_.explore_force_n);
    } else {
      SetFinger(static_cast<int>(k), Role::kGrip, Primitive::kComposite);
    }
  }
  out_.task.has_object_target = has_goal_;
  out_.task.object_target = goal_;
}

void Supervisor::Rotate(const std::string& grippers) {
  (void)grippers;  // the explorer, if any, keeps exploring in place; the others grip
  phase_since_ = now_;
  NewTask(regrasp_.last_action());
  if (task_params_.has_goals()) {
    // One step from where the object is toward the current goal, the shortest way.
    const AxisAngle to_goal = RotationToGoal(SensedOrientation(), goals_.current());
    step_ = std::min(task_params_.step, to_goal.angle);
    goal_.linear() =
        (Eigen::AngleAxisd(step_, to_goal.axis) * SensedOrientation()).toRotationMatrix();
    has_goal_ = true;
    rotation_commanded_ += step_;
    out_.task.has_object_target = true;
    out_.task.object_target = goal_;
    out_.task.max_angular_speed = StepSpeed();
    motion_done_event_ = false;
    return;
  }
  const double remaining = rotation_goal_ - rotation_commanded_;
  step_ = std::copysign(std::min(task_params_.step, std::abs(remaining)), remaining);
  RotateGoal(Axis("task"), step_);
}

void Supervisor::Grip(const std::string& finger) {
  phase_since_ = now_;
  explorer_ = -1;
  NewTask(regrasp_.last_action());
  SetFinger(Finger(finger), Role::kGrip, Primitive::kComposite);
}

void Supervisor::Finish() { gait_done_ = true; }

Eigen::Vector3d Supervisor::StepAxis() const {
  return task_params_.has_goals() ? RotationToGoal(SensedOrientation(), goals_.current()).axis
                                  : Axis("task");
}

bool Supervisor::CanTurnWithout(const std::string& /*finger*/) const {
  // The fingers stand around one axis of the palm (gait.overlap_about): about it, any three of
  // them turn the object while the fourth slides back; about an axis tilted from it they push
  // the object along that axis too, which needs the fourth's support (measured: three alone
  // lose the object about y, z and the diagonal; four turn it).
  const Eigen::Vector3d about(tasks_.gait.overlap_about[0], tasks_.gait.overlap_about[1],
                              tasks_.gait.overlap_about[2]);
  const double cos_tilt = std::abs(StepAxis().dot(about.normalized()));
  return cos_tilt >= std::cos(tasks_.gait.overlap_max_tilt_rad);
}

bool Supervisor::GoalReached() const {
  if (task_params_.has_goals()) return goals_.complete();
  return std::abs(rotation_goal_ - rotation_commanded_) < 1e-9;
}

void Supervisor::SetProcessLost(bool lost, const std::string& who) {
  if (lost == process_lost_) return;
  process_lost_ = lost;
  if (lost) {
    note_ = "process '" + who + "' stopped beating";
    grasp_.Process(GraspEvent::ProcessLost);
  } else {
    note_ = "process '" + who + "' is back";
    grasp_.Process(GraspEvent::ProcessBack);
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
          note_ = "finger " + fingers_[f] + " found no object";
          grasp_.Process(GraspEvent::Timeout);
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
    note_ = "task '" + task.name + "' did not finish within " + std::to_string(task.timeout_s) + " s";
    grasp_.Process(GraspEvent::TaskFailed);
  }
}

bool Supervisor::StepDone(double in_phase) const {
  // The reference needs |step| / speed to arrive; after that and a moment to settle, an object
  // close enough to its goal has done its step.
  const GaitSpec& g = tasks_.gait;
  const double travel = std::abs(step_) / StepSpeed();
  const bool settled = in_phase > travel + g.settle_time_s &&
                       view_.tracking_error_rad < g.settle_tolerance_rad;
  return motion_done_event_ || view_.motion_done || settled;
}

void Supervisor::TickGoals() {
  switch (goals_.Update(now_, SensedOrientation())) {
    case GoalSequence::Event::kReached:
      Note("goal " + std::to_string(goals_.reached()) + " of " + std::to_string(goals_.size()) +
           " reached in " + Fixed(goals_.times_s().back()) + " s");
      if (goals_.complete()) gait_done_ = true;
      break;
    case GoalSequence::Event::kTimedOut:
      note_ = "goal " + std::to_string(goals_.reached() + 1) + " not reached within " +
              Fixed(task_params_.goal_timeout_s, 1) + " s (" + Fixed(goals_.error_rad()) +
              " rad from it)";
      grasp_.Process(GraspEvent::TaskFailed);
      break;
    case GoalSequence::Event::kNone:
      break;
  }
}

void Supervisor::TickGait() {
  const GaitSpec& g = tasks_.gait;
  const double in_phase = now_ - phase_since_;
  if (task_params_.has_goals()) {
    TickGoals();
    if (!grasp_.is(GraspState::Tasks)) return;
  }
  if (regrasp_.exploring()) {
    const bool there = explorer_ >= 0 && reached_[explorer_] && view_.fingers[explorer_].in_contact;
    // Continuous: the three turn the object while the explorer slides; both must be done.
    const bool turned = !regrasp_.overlapping() || StepDone(in_phase);
    if ((there && turned) || in_phase > g.explore_timeout_s) {
      if (!there) Note("explorer " + fingers_[explorer_] + " did not reach its point in time");
      if (!turned) Note("the step did not finish while the explorer slid");
      regrasp_.Process(RegraspEvent::ExploreReady);
    }
  } else if (regrasp_.rotating()) {
    if (StepDone(in_phase)) {
      if (!(motion_done_event_ || view_.motion_done)) {
        Note("step settled " + std::to_string(view_.tracking_error_rad) + " rad short");
      }
      regrasp_.Process(RegraspEvent::RotateDone);
    } else if (in_phase > g.rotate_timeout_s) {
      note_ = "a rotation step did not finish within " + std::to_string(g.rotate_timeout_s) + " s";
      grasp_.Process(GraspEvent::Slip);
    }
  } else {
    // Gripping: wait for a stable grasp (at least a moment after the role change).
    if ((view_.grasp_stable && in_phase > 0.05) || in_phase > g.grip_timeout_s) {
      if (!view_.grasp_stable) Note("no stable grasp within the grip timeout; going on");
      regrasp_.Process(RegraspEvent::GripStable);
    }
  }
  if (gait_done_) grasp_.Process(GraspEvent::TaskDone);
}

const SupervisorOutput& Supervisor::Step(const ControllerView& view) {
  DMPL_DEMAND(view.fingers.size() == fingers_.size());
  view_ = view;
  now_ = view.time_s;
  out_.sim = SimRequest::kNone;
  out_.changed = false;
  const GraspState before = grasp_.state();
  if (grasp_.is(GraspState::ObjectHeld)) grasp_.Process(GraspEvent::Start);

  // Controller events -> chart events.
  for (const ControllerEvent& e : view.events) {
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
          note_ = "finger " + fingers_[e.finger] + " lost its grip contact";
          grasp_.Process(GraspEvent::ContactLost);
        }
        break;
      case EventType::kTrackingError:
        if (grasp_.is(GraspState::Tasks)) {
          note_ = "the object slipped (" + e.text + ")";
          grasp_.Process(GraspEvent::Slip);
        }
        break;
      case EventType::kGraspLost:
        if (release_sent_) {
          note_ = "the object is lost: " + e.text;
          grasp_.Process(GraspEvent::GraspLost);
        }
        break;
      default:
        break;
    }
  }

  switch (grasp_.state()) {
    case GraspState::Approaching:
      TickApproach();
      if (now_ - state_since_ > tasks_.grasp.timeout_s && grasp_.is(GraspState::Approaching)) {
        note_ = "the fingers did not all touch within " + std::to_string(tasks_.grasp.timeout_s) + " s";
        grasp_.Process(GraspEvent::Timeout);
      }
      break;
    case GraspState::Gripping:
      if (view.grasp_stable) {
        grasp_.Process(GraspEvent::GraspStable);
      } else if (now_ - state_since_ > tasks_.grasp.timeout_s) {
        note_ = "no stable grasp within " + std::to_string(tasks_.grasp.timeout_s) + " s";
        grasp_.Process(GraspEvent::Timeout);
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
      if (tasks_.tasks[task_index_].type == "gait") {
        TickGait();
      } else {
        TickLocalTask();
      }
      break;
    case GraspState::Recovering: {
      bool all_touch = true;
      for (const auto& f : view.fingers) all_touch = all_touch && f.in_contact;
      if (view.grasp_stable && all_touch && now_ - state_since_ > 0.1) {
        grasp_.Process(GraspEvent::Recovered);
      } else if (now_ - state_since_ > params_.recovery_timeout_s) {
        note_ = "no stable grasp within the recovery timeout";
        grasp_.Process(GraspEvent::Timeout);
      }
      break;
    }
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
  if (grasp_.state() != before) out_.changed = true;
  if (out_.changed) last_action_ = regrasp_.last_action();
  return out_;
}

}  // namespace dmpl
