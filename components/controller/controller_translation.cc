#include "components/controller/controller_translation.h"

#include "components/runtime/lcm_eigen.h"

namespace dmpl {

SensedInput ToSensedInput(const hand_sensors_t& m, const HandKinematics& kin,
                          const std::vector<SensedTip>& previous) {
  SensedInput in;
  in.q = m.joints.position;
  in.effort = m.joints.effort;
  in.seq = m.seq;
  in.time_s = m.utime * 1e-6;
  in.tips = previous;
  for (const auto& t : m.tactile.fingers) {
    const int f = kin.FindFinger(t.finger);
    if (f >= 0) in.tips[f] = {t.in_contact != 0, ToVector3(t.position), t.force_n};
  }
  in.object_valid = m.object.valid;
  in.object = ToPose(m.object.position, m.object.orientation);
  in.gravity = ToVector3(m.gravity);
  return in;
}

TaskInput ToTaskInput(const task_cmd_t& m, const HandKinematics& kin,
                      std::vector<std::string>* unknown) {
  TaskInput t;
  t.task_id = m.task_id;
  t.name = m.name;
  t.has_object_target = m.has_object_target;
  t.object_target = ToPose(m.object_position, m.object_orientation);
  t.max_linear_speed = m.max_linear_speed;
  t.max_angular_speed = m.max_angular_speed;
  t.fingers.resize(kin.num_fingers());
  for (const auto& fp : m.fingers) {
    const int f = kin.FindFinger(fp.finger);
    if (f < 0) {
      unknown->push_back(fp.finger);
      continue;
    }
    FingerTask& ft = t.fingers[f];
    ft.role = static_cast<Role>(fp.role);
    ft.primitive = static_cast<Primitive>(fp.primitive);
    ft.has_target = fp.has_target;
    ft.target = ToVector3(fp.target_position);
    ft.force_n = fp.force_n;
    ft.face_surface = fp.face_surface;
  }
  return t;
}

void FillTargets(const ControllerOutput& out, const SensedInput& sensed, int64_t tick,
                 finger_targets_t* targets) {
  targets->utime = static_cast<int64_t>(sensed.time_s * 1e6 + 0.5);
  targets->seq = tick;
  targets->joint_position = sensed.q;
  targets->num_joints = static_cast<int16_t>(sensed.q.size());
  for (size_t f = 0; f < out.fingers.size(); ++f) {
    finger_target_t& t = targets->fingers[f];
    t.mode = out.fingers[f].track ? finger_target_t::POSITION : finger_target_t::HOLD;
    ToArray(out.fingers[f].target, t.position);
    ToArray(out.fingers[f].approach, t.approach);
  }
}

void FillStatus(const ControllerOutput& out, int64_t tick, int64_t utime,
                const HandKinematics& kin, controller_status_t* status) {
  controller_status_t& s = *status;
  s.utime = utime;
  s.seq = tick;
  s.task_id = out.task_id;
  s.motion_done = out.motion_done;
  s.grasp_stable = out.grasp_stable;
  s.tracking_error_rad = out.tracking_error_rad;
  s.grip_force_n = out.grip_force_n;
  s.load_scale = out.load_scale;
  s.observed_friction = out.observed_friction;
  s.observed_weight_n = out.observed_weight_n;
  ToArray(out.gravity, s.gravity);
  s.tracking_error_m = out.tracking_error_m;
  ToArray(Eigen::Vector3d(out.object_estimate.translation()), s.object_position);
  ToArray(Eigen::Quaterniond(out.object_estimate.linear()), s.object_orientation);
  ToArray(out.contact_centroid, s.contact_centroid);
  for (size_t f = 0; f < out.fingers.size(); ++f) {
    const FingerOutput& o = out.fingers[f];
    finger_status_t& fs = s.fingers[f];
    fs.role = static_cast<int8_t>(o.role);
    fs.primitive = static_cast<int8_t>(o.primitive);
    fs.in_contact = o.in_contact;
    fs.force_n = o.force;
    fs.desired_force_n = o.desired_force;
    ToArray(o.tip, fs.tip_position);
    ToArray(o.target, fs.target_position);
    ToArray(o.contact, fs.contact_position);
    ToArray(o.tip_axis, fs.tip_axis);
  }
  s.events.clear();
  for (const ControllerEvent& e : out.events) {
    controller_event_t ev;
    ev.type = static_cast<int8_t>(e.type);
    ev.finger = e.finger >= 0 ? kin.finger(e.finger).name() : "";
    ev.value = e.value;
    ev.text = e.text;
    s.events.push_back(ev);
  }
  s.num_events = static_cast<int16_t>(s.events.size());
}

}  // namespace dmpl
