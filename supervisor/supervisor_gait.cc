// Finger gaiting: the regrasp chart's actions (explore, rotate, grip), the steps toward the goal
// and the goal orientations.
#include "supervisor/supervisor.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "components/runtime/check.h"

namespace dmpl {

namespace {

std::string Fixed(double value, int digits = 2) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << value;
  return os.str();
}

// An orthonormal basis (u, v) of the plane normal to `axis` (unit).
void PlaneBasis(const Eigen::Vector3d& axis, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  *u = axis.unitOrthogonal();
  *v = axis.cross(*u);
}
double AngleAbout(const Eigen::Vector3d& p, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(p.dot(v), p.dot(u));
}
double Radial(const Eigen::Vector3d& p, const Eigen::Vector3d& axis) {
  return (p - p.dot(axis) * axis).norm();
}
double WrapPi(double a) { return std::remainder(a, 2.0 * M_PI); }
// The angle two fingertips `clearance` apart need at `radius` from the axis.
double GapAngle(double clearance, double radius) {
  return radius <= 0 ? M_PI : 2.0 * std::asin(std::min(1.0, clearance / (2.0 * radius)));
}

}  // namespace

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
  const bool spaced = tasks_.gait.tip_clearance_m > 0 && AroundFingers(axis);
  step_limit_ = spaced ? GaitStepLimit(axis) : 0.0;
  const double step = StepSize();
  double back = -sign * task_params_.explore_travel * rides * step / 2.0;
  if (LimitDeviation()) {
    // No further back than the deviation allows: a turn by phi about the axis moves a point at
    // beta from it by 2 asin(sin(beta) sin(phi / 2)).
    const Eigen::Vector3d home = (home_[f] - home_centre_).normalized();
    const double sin_beta = axis.normalized().cross(home).norm();
    const double d = task_params_.max_finger_deviation_rad;
    const double most =
        sin_beta <= std::sin(d / 2) ? M_PI : 2.0 * std::asin(std::sin(d / 2) / sin_beta);
    back = std::copysign(std::min(std::abs(back), most), back);
  }
  const Eigen::AngleAxisd turn(back, axis);
  explore_point_ = view_.object.translation() + turn * (home_[f] - home_centre_);
  explore_axis_ = axis;
  explore_spaced_ = spaced;
  explore_neighbour_rides_ = !four;
  explore_sign_ = sign;
  explore_target_ = spaced ? KeepClear(f, axis, sign, step, !four, explore_point_) : explore_point_;
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

void Supervisor::Rotate(const std::vector<std::string>& grippers) {
  (void)grippers;  // the explorer, if any, keeps exploring in place; the others grip
  phase_since_ = now_;
  NewTask(regrasp_.last_action());
  if (task_params_.has_goals()) {
    // One step from where the object is toward the current goal, the shortest way.
    const AxisAngle to_goal = RotationToGoal(SensedOrientation(), goals_.current());
    step_ = std::min(StepSize(), to_goal.angle);
    if (LimitDeviation()) {
      // The explorer, if it slides meanwhile, does not ride this step.
      const int skip = regrasp_.exploring() ? explorer_ : -1;
      step_ = StepWithinReach(to_goal.axis, step_, skip);
      ChooseNextExplorer(to_goal.axis, step_ + StepSize(), skip);
    }
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
  step_ = std::copysign(std::min(StepSize(), std::abs(remaining)), remaining);
  RotateGoal(Axis("task"), step_);
}

void Supervisor::Grip(const std::string& finger) {
  phase_since_ = now_;
  explorer_ = -1;
  NewTask(regrasp_.last_action());
  SetFinger(Finger(finger), Role::kGrip, Primitive::kComposite);
  if (LimitDeviation()) ChooseNextExplorer(StepAxis(), StepSize(), -1);
}

double Supervisor::Deviation(int k, const Eigen::AngleAxisd& turn) const {
  const Eigen::Vector3d home = home_[k] - home_centre_;
  const Eigen::Vector3d now = turn * (view_.fingers[k].tip - view_.object.translation());
  const double c = home.dot(now) / (home.norm() * now.norm());
  return std::acos(std::clamp(c, -1.0, 1.0));
}

double Supervisor::StepWithinReach(const Eigen::Vector3d& axis_in, double step, int skip) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  const double limit = task_params_.max_finger_deviation_rad;
  // Each riding finger's bound: the limit, or where it stands if it is already beyond.
  std::vector<double> bound(fingers_.size(), 0.0);
  for (size_t k = 0; k < fingers_.size(); ++k) {
    bound[k] = std::max(limit, Deviation(static_cast<int>(k), Eigen::AngleAxisd(0.0, axis)));
  }
  constexpr int kSamples = 16;
  double allowed = 0.0;
  for (int i = 1; i <= kSamples; ++i) {
    const double phi = step * i / kSamples;
    for (size_t k = 0; k < fingers_.size(); ++k) {
      if (static_cast<int>(k) == skip || !view_.fingers[k].in_contact) continue;
      if (Deviation(static_cast<int>(k), Eigen::AngleAxisd(phi, axis)) > bound[k]) return allowed;
    }
    allowed = phi;
  }
  return allowed;
}

void Supervisor::ChooseNextExplorer(const Eigen::Vector3d& axis, double step, int skip) {
  int next = -1;
  double furthest = -1.0;
  for (size_t k = 0; k < fingers_.size(); ++k) {
    if (static_cast<int>(k) == skip) continue;
    const double d = Deviation(static_cast<int>(k), Eigen::AngleAxisd(step, axis.normalized()));
    if (d > furthest) {
      furthest = d;
      next = static_cast<int>(k);
    }
  }
  if (next >= 0) regrasp_.set_next_explorer(fingers_[next]);
}

void Supervisor::Finish() { gait_done_ = true; }

Eigen::Vector3d Supervisor::StepAxis() const {
  return task_params_.has_goals() ? RotationToGoal(SensedOrientation(), goals_.current()).axis
                                  : Axis("task");
}

double Supervisor::StepSize() const {
  return step_limit_ > 0 ? std::min(task_params_.step, step_limit_) : task_params_.step;
}

bool Supervisor::AroundFingers(const Eigen::Vector3d& axis) const {
  const Eigen::Vector3d about(tasks_.gait.overlap_about[0], tasks_.gait.overlap_about[1],
                              tasks_.gait.overlap_about[2]);
  return std::abs(axis.normalized().dot(about.normalized())) >=
         std::cos(tasks_.gait.overlap_max_tilt_rad);
}

double Supervisor::GaitStepLimit(const Eigen::Vector3d& axis_in) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  const size_t n = fingers_.size();
  // Only for fingers that stand around the axis (their homes at distinct angles about it).
  Eigen::Vector3d u, v;
  PlaneBasis(axis, &u, &v);
  std::vector<double> angles;
  for (size_t k = 0; k < n; ++k) angles.push_back(AngleAbout(home_[k] - home_centre_, u, v));
  std::sort(angles.begin(), angles.end());
  for (size_t k = 1; k < n; ++k) {
    if (!(angles[k] - angles[k - 1] > 1e-6)) return 0.0;
  }
  // How far the fingertips stand from the axis now (the closest one: an elongated section
  // brings some closer).
  const Eigen::Vector3d centre = view_.object.translation();
  double radius = 0.0;
  bool any = false;
  for (size_t k = 0; k < n; ++k) {
    if (!view_.fingers[k].in_contact) continue;
    const double r = Radial(view_.fingers[k].tip - centre, axis);
    radius = any ? std::min(radius, r) : r;
    any = true;
  }
  if (!any || !(radius > 0)) return 0.0;
  // The fingers stand around the axis 2 pi / n apart on average (a grasp that left two closer
  // leaves two further apart, and KeepClear keeps an explorer off the closer one).
  const double spacing = 2.0 * M_PI / static_cast<double>(n);
  const double limit =
      (spacing - GapAngle(tasks_.gait.tip_clearance_m, radius)) / static_cast<double>(n - 1);
  // Too small an object to gait at all with these fingers: the smallest steps still try.
  return std::max(limit, task_params_.step / 4.0);
}

Eigen::Vector3d Supervisor::KeepClear(int explorer, const Eigen::Vector3d& axis_in, double sign,
                                      double step, bool neighbour_rides,
                                      const Eigen::Vector3d& target) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  Eigen::Vector3d u, v;
  PlaneBasis(axis, &u, &v);
  const Eigen::Vector3d centre = view_.object.translation();
  const double own = AngleAbout(view_.fingers[explorer].tip - centre, u, v);
  // The finger the explorer slides back toward: the nearest one behind it.
  int neighbour = -1;
  double nearest = 2.0 * M_PI;
  for (size_t k = 0; k < fingers_.size(); ++k) {
    if (static_cast<int>(k) == explorer) continue;
    double behind = sign * (own - AngleAbout(view_.fingers[k].tip - centre, u, v));
    behind = std::fmod(behind + 4.0 * M_PI, 2.0 * M_PI);
    if (behind < nearest) {
      nearest = behind;
      neighbour = static_cast<int>(k);
    }
  }
  if (neighbour < 0) return target;
  const Eigen::Vector3d other = view_.fingers[neighbour].tip - centre;
  const double other_end = AngleAbout(other, u, v) + (neighbour_rides ? sign * step : 0.0);
  const Eigen::Vector3d offset = target - centre;
  const double ahead = WrapPi(sign * (AngleAbout(offset, u, v) - other_end));
  const double gap = GapAngle(tasks_.gait.tip_clearance_m,
                              std::min(Radial(offset, axis), Radial(other, axis)));
  if (ahead >= gap) return target;
  return centre + Eigen::AngleAxisd(sign * (gap - ahead), axis) * offset;
}

void Supervisor::KeepExplorerClear() {
  if (!explore_spaced_ || explorer_ < 0) return;
  // About the axis the explore began with: a goal reached meanwhile turns the next steps about
  // another one, and the explorer's point was chosen for this one.
  const Eigen::Vector3d axis = explore_axis_.normalized();
  // What the step still has to turn about the axis: the finger it slides toward rides it.
  double remaining = 0.0;
  if (explore_neighbour_rides_ && has_goal_) {
    const Eigen::AngleAxisd left(goal_.linear() * view_.object.linear().transpose());
    remaining = std::clamp(std::abs(left.angle() * left.axis().dot(axis)), 0.0, std::abs(step_));
  }
  const Eigen::Vector3d target =
      KeepClear(explorer_, axis, explore_sign_, remaining, explore_neighbour_rides_,
                explore_point_);
  if ((target - explore_target_).norm() < 1e-3) return;  // not for the estimate's noise
  explore_target_ = target;
  out_.task.fingers[explorer_].target = target;
  reached_[explorer_] = false;
  out_.changed = true;
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
      recoveries_counted_ = 0;
      if (goals_.complete()) gait_done_ = true;
      break;
    case GoalSequence::Event::kTimedOut:
      grasp_.Process(GraspEvent::TaskFailed,
                     {"goal " + std::to_string(goals_.reached() + 1) + " not reached within " +
                      Fixed(task_params_.goal_timeout_s, 1) + " s (" + Fixed(goals_.error_rad()) +
                      " rad from it)"});
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
    KeepExplorerClear();
    const bool there = explorer_ >= 0 && reached_[explorer_] && view_.fingers[explorer_].in_contact;
    // Continuous: the three turn the object while the explorer slides; both must be done.
    const bool turned = !regrasp_.overlapping() || StepDone(in_phase);
    if ((there && turned) || in_phase > g.explore_timeout_s) {
      if (!there) Note("explorer " + fingers_[explorer_] + " did not reach its point in time");
      if (!turned) Note("the step did not finish while the explorer slid");
      regrasp_.Process(RegraspEvent::ExploreReady);
    }
  } else if (regrasp_.rotating()) {
    // A turn that began with a grip waits for the grasp to be stable too (as a grip would).
    const bool gripped = !regrasp_.gripping_while_turning() ||
                         (view_.grasp_stable && in_phase > 0.05) || in_phase > g.grip_timeout_s;
    if (StepDone(in_phase) && gripped) {
      if (!(motion_done_event_ || view_.motion_done)) {
        Note("step settled " + std::to_string(view_.tracking_error_rad) + " rad short");
      }
      if (!view_.grasp_stable && regrasp_.gripping_while_turning()) {
        Note("no stable grasp within the grip timeout; going on");
      }
      regrasp_.Process(RegraspEvent::RotateDone);
    } else if (in_phase > g.rotate_timeout_s) {
      grasp_.Process(GraspEvent::Slip, {"a rotation step did not finish within " +
                                        std::to_string(g.rotate_timeout_s) + " s"});
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

}  // namespace dmpl
