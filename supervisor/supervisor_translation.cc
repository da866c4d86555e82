#include "supervisor/supervisor_translation.h"

#include <algorithm>
#include <cmath>

#include "components/kinematics/hand_kinematics.h"
#include "components/runtime/lcm_eigen.h"

namespace dmpl {

namespace {

int Index(const std::vector<std::string>& fingers, const std::string& finger) {
  const auto it = std::find(fingers.begin(), fingers.end(), finger);
  return it == fingers.end() ? -1 : static_cast<int>(it - fingers.begin());
}

}  // namespace

std::string OutOfRange(const controller_status_t& m) {
  const Eigen::Vector3d object = ToVector3(m.object_position);
  if (!object.allFinite() || object.norm() > InputBounds::kWorkspaceRadiusM) {
    return "object estimate outside the hand's workspace";
  }
  for (double q : m.object_orientation) {
    if (!std::isfinite(q)) return "object orientation with NaN";
  }
  for (const auto& f : m.fingers) {
    const Eigen::Vector3d tip = ToVector3(f.tip_position);
    if (!tip.allFinite() || tip.norm() > InputBounds::kWorkspaceRadiusM) {
      return "finger " + f.finger + " tip outside the hand's workspace";
    }
    if (!ToVector3(f.tip_axis).allFinite() || !ToVector3(f.contact_position).allFinite()) {
      return "finger " + f.finger + " contact or tip axis with NaN";
    }
    if (!std::isfinite(f.force_n) || std::abs(f.force_n) > InputBounds::kMaxForceN) {
      return "finger " + f.finger + " force beyond the sensor's range";
    }
    if (!std::isfinite(f.desired_force_n) ||
        std::abs(f.desired_force_n) > InputBounds::kMaxForceN) {
      return "finger " + f.finger + " planned force beyond the sensor's range";
    }
  }
  return "";
}

ControllerView ToControllerView(const controller_status_t& m,
                                const std::vector<std::string>& fingers) {
  ControllerView view;
  view.seq = m.seq;
  view.time_s = m.utime * 1e-6;
  view.fingers.resize(fingers.size());
  for (const auto& fs : m.fingers) {
    const int f = Index(fingers, fs.finger);
    if (f < 0) continue;
    view.fingers[f] = {fs.in_contact != 0, fs.force_n, ToVector3(fs.tip_position),
                       ToVector3(fs.contact_position), ToVector3(fs.tip_axis), fs.desired_force_n};
    const double axis = view.fingers[f].tip_axis.norm();
    view.fingers[f].tip_axis =
        axis > 0.5 ? Eigen::Vector3d(view.fingers[f].tip_axis / axis) : Eigen::Vector3d::UnitZ();
  }
  view.object = ToPose(m.object_position, m.object_orientation);
  for (const auto& e : m.events) {
    view.events.push_back({static_cast<EventType>(e.type), Index(fingers, e.finger), e.value,
                           e.text});
  }
  view.motion_done = m.motion_done;
  view.grasp_stable = m.grasp_stable;
  view.tracking_error_rad = m.tracking_error_rad;
  const Eigen::Vector3d gravity = ToVector3(m.gravity);
  // A direction, or nothing: a message from outside may carry anything.
  if (gravity.allFinite() && std::abs(gravity.norm() - 1.0) < 0.1) {
    view.gravity = gravity.normalized();
  }
  if (std::isfinite(m.observed_friction) && m.observed_friction > 0.0) {
    view.observed_friction = m.observed_friction;
  }
  if (std::isfinite(m.observed_weight_n) && m.observed_weight_n > 0.0) {
    view.observed_weight_n = m.observed_weight_n;
  }
  return view;
}

void LearnFromStatus(const controller_status_t& m, std::unique_ptr<Blackboard>* board) {
  if (!*board) {
    std::vector<std::string> fingers;
    for (const auto& f : m.fingers) fingers.push_back(f.finger);
    *board = std::make_unique<Blackboard>(std::move(fingers));
  }
  Blackboard& b = **board;
  b.view = ToControllerView(m, b.fingers);
  b.now = b.view.time_s;
  b.LearnSurface();
}

task_cmd_t ToTaskMessage(const TaskInput& t, const std::vector<std::string>& fingers, int64_t seq,
                         int64_t utime, SimRequest sim, const std::string& reason) {
  task_cmd_t m{};
  m.sim_command = static_cast<int8_t>(sim);
  m.sim_command_reason = reason;
  m.utime = utime;
  m.seq = seq;
  m.task_id = t.task_id;
  m.name = t.name;
  m.has_object_target = t.has_object_target;
  ToArray(Eigen::Vector3d(t.object_target.translation()), m.object_position);
  ToArray(Eigen::Quaterniond(t.object_target.linear()), m.object_orientation);
  m.max_linear_speed = t.max_linear_speed;
  m.max_angular_speed = t.max_angular_speed;
  for (size_t f = 0; f < fingers.size(); ++f) {
    finger_primitive_t p{};
    p.finger = fingers[f];
    p.role = static_cast<int8_t>(t.fingers[f].role);
    p.primitive = static_cast<int8_t>(t.fingers[f].primitive);
    p.has_target = t.fingers[f].has_target;
    for (int i = 0; i < 3; ++i) p.target_position[i] = t.fingers[f].target[i];
    p.force_n = t.fingers[f].force_n;
    p.face_surface = t.fingers[f].face_surface;
    m.fingers.push_back(p);
  }
  m.num_fingers = static_cast<int8_t>(m.fingers.size());
  return m;
}

supervisor_status_t ToStatusMessage(const Supervisor& core, int64_t seq, int64_t utime) {
  supervisor_status_t s{};
  s.utime = utime;
  s.seq = seq;
  s.grasp_state = ToString(core.grasp_state());
  s.regrasp_state = ToString(core.regrasp().state());
  s.last_action = core.regrasp().last_action();
  s.task_name = core.task_name();
  s.task_index = core.task_index();
  s.num_tasks = core.num_tasks();
  s.finger = core.fingers();
  for (Role r : core.roles()) s.role.push_back(static_cast<int8_t>(r));
  s.num_fingers = static_cast<int8_t>(core.fingers().size());
  s.rotation_commanded_rad = core.rotation_commanded();
  s.rotation_goal_rad = core.rotation_goal();
  s.regrasps = core.regrasp().regrasps();
  s.recoveries = core.recoveries();
  s.holding = core.holding();
  s.finished = core.finished();
  s.failed = core.failed();
  s.note = core.note();
  const GoalSequence& goals = core.goals();
  s.num_goals = goals.size();
  s.goals_reached = goals.reached();
  s.has_orientation_goal = !goals.empty();
  ToArray(goals.empty() ? Eigen::Quaterniond::Identity() : goals.current(), s.orientation_goal);
  s.goal_error_rad = goals.error_rad();
  return s;
}

}  // namespace dmpl
