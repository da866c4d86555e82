#include "components/controller/manipulation_controller.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "components/controller/contact_sensing.h"
#include "components/controller/position_planner.h"
#include "components/runtime/check.h"

namespace dmpl {
namespace {

Eigen::Vector3d ClampNorm(const Eigen::Vector3d& v, double max_norm) {
  const double n = v.norm();
  return n > max_norm ? Eigen::Vector3d(v * (max_norm / n)) : v;
}

}  // namespace

// The bounds of single keys are declared beside them (controller_params.h); what relates two
// keys is checked here.
void ControllerParams::Validate(const std::string& source) const {
  CheckBounds(*this, source, "controller");
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'controller." + key + "': " + what);
  };
  if (min_grip_force_n > grip_force_n) fail("min_grip_force_n", "must be <= grip_force_n");
  if (!(grip_adaptation.max_grip_force_n >= grip_force_n)) {
    fail("grip_adaptation.max_grip_force_n", "must be >= grip_force_n");
  }
  if (!(normals_aim.max_force_n >= grip_force_n)) {
    fail("normals_aim.max_force_n", "must be >= grip_force_n");
  }
  // More samples asked than kept: nothing would ever be observed.
  if (friction_observer.min_samples > friction_observer.window) {
    fail("friction_observer.min_samples", "must be <= friction_observer.window");
  }
  if (weight_observer.min_samples > weight_observer.window) {
    fail("weight_observer.min_samples", "must be <= weight_observer.window");
  }
}

ManipulationController::ManipulationController(const HandKinematics& kinematics,
                                               const ControllerParams& params, double tick_s)
    : kin_(kinematics),
      params_(params),
      dt_(tick_s),
      fingers_(kinematics.num_fingers()),
      grip_(params.grip_adaptation, params.grip_force_n),
      load_(params.load),
      friction_(params.friction_observer),
      weight_(params.weight_observer),
      sink_(params.sink_detector) {
  DMPL_DEMAND(tick_s > 0);
  out_.fingers.resize(kinematics.num_fingers());
  max_linear_ = params_.max_linear_speed;
  max_angular_ = params_.max_angular_speed;
}

void ManipulationController::Emit(EventType type, int finger, double value, std::string text) {
  out_.events.push_back({type, finger, value, std::move(text)});
}

bool ManipulationController::Validate(const SensedInput& in, std::string* why) const {
  if (static_cast<int>(in.q.size()) != kin_.num_joints()) {
    *why = "joint state with " + std::to_string(in.q.size()) + " joints";
    return false;
  }
  if (static_cast<int>(in.tips.size()) != kin_.num_fingers()) {
    *why = "tactile reading with " + std::to_string(in.tips.size()) + " fingers";
    return false;
  }
  for (double q : in.q) {
    if (!std::isfinite(q)) {
      *why = "joint state with NaN";
      return false;
    }
  }
  if (std::string out = kin_.OutOfLimits(in.q, InputBounds::kJointMarginRad); !out.empty()) {
    *why = "joint state beyond the hand's limits: " + out;
    return false;
  }
  for (const auto& t : in.tips) {
    if (!t.position.allFinite() || !std::isfinite(t.force)) {
      *why = "tactile reading with NaN";
      return false;
    }
    if (std::abs(t.force) > InputBounds::kMaxForceN ||
        t.position.norm() > InputBounds::kWorkspaceRadiusM) {
      *why = "tactile reading beyond the sensor's range (" + std::to_string(t.force) + " N at " +
             std::to_string(t.position.norm()) + " m from the palm)";
      return false;
    }
  }
  if (!in.gravity.allFinite() || !(in.gravity.norm() > InputBounds::kMinGravity) ||
      in.gravity.norm() > InputBounds::kMaxGravity) {
    *why = "gravity reading of " + std::to_string(in.gravity.norm()) +
           " m/s^2 (the palm's IMU: expected about 9.8)";
    return false;
  }
  if (in.object_valid && !in.object.matrix().allFinite()) {
    *why = "object pose with NaN";
    return false;
  }
  if (in.object_valid && in.object.translation().norm() > InputBounds::kWorkspaceRadiusM) {
    *why = "object pose " + std::to_string(in.object.translation().norm()) +
           " m from the palm, outside the hand's workspace";
    return false;
  }
  return true;
}

// Gravity's direction in the palm frame, from the palm's IMU: low-passed (its noise), and
// followed as the palm turns.
void ManipulationController::UpdateGravity(const SensedInput& in) {
  const Eigen::Vector3d down = in.gravity.normalized();
  if (!has_gravity_) {
    gravity_ = down;
    has_gravity_ = true;
  } else {
    const double a = dt_ / (params_.gravity_time_constant_s + dt_);
    gravity_ = (gravity_ + a * (down - gravity_)).normalized();
  }
  out_.gravity = gravity_;
}

void ManipulationController::UpdateObjectEstimate(const SensedInput& in) {
  if (!in.object_valid) return;  // dropped reading: keep the estimate
  if (!has_estimate_) {
    estimate_ = in.object;
    has_estimate_ = true;
    return;
  }
  // First-order low-pass: the paper's 0.5 cm noise would otherwise shake every finger by 5 mm.
  const double ap = dt_ / (params_.object_position_time_constant_s + dt_);
  const double ao = dt_ / (params_.object_orientation_time_constant_s + dt_);
  estimate_.translation() += ap * (in.object.translation() - estimate_.translation());
  const Eigen::Quaterniond q0(estimate_.linear()), q1(in.object.linear());
  estimate_.linear() = q0.slerp(ao, q1).normalized().toRotationMatrix();
}

void ManipulationController::UpdateContacts(const SensedInput& in) {
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    FingerState& s = fingers_[f];
    const bool raw = in.tips[f].in_contact && in.tips[f].force > params_.contact_threshold_n;
    if (!has_contacts_) {
      // No history to debounce against: the first reading is the state (a controller restarted
      // mid-grasp holds the object at once; at a run's start every finger is open anyway).
      s.contact = raw;
      continue;
    }
    if (raw == s.contact) {
      s.contact_count = 0;
      continue;
    }
    const int needed = raw ? params_.contact_debounce_ticks : params_.contact_loss_ticks;
    if (++s.contact_count < needed) continue;
    s.contact = raw;
    s.contact_count = 0;
    if (raw) {
      Emit(EventType::kContactMade, f, in.tips[f].force, kin_.finger(f).name() + " touches");
    } else {
      Emit(EventType::kContactLost, f, static_cast<double>(s.task.role),
           kin_.finger(f).name() + (s.task.role == Role::kGrip ? " lost its grip contact"
                                                               : " left the surface"));
    }
  }
  has_contacts_ = true;
}

void ManipulationController::DetectLinkContacts(const SensedInput& in,
                                                const std::vector<Eigen::Vector3d>& tips) {
  const double threshold = params_.link_contact_torque_nm;
  if (threshold <= 0 || in.effort.size() != in.q.size()) return;
  for (const double tau : in.effort) {
    if (!std::isfinite(tau)) return;  // not a reading to act on
  }
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    const SensedTip& tip = in.tips[f];
    // The normal's direction needs no tip radius.
    const Eigen::Vector3d normal =
        tip.in_contact ? NormalFromTip(tips[f], tip.position, 0.0).normal : Eigen::Vector3d::Zero();
    const LinkContact link = FindLinkContact(kin_, f, in.q, in.effort,
                                             tip.in_contact ? tip.force : 0.0, normal, threshold,
                                             params_.link_contact_friction);
    FingerState& s = fingers_[f];
    const bool raw = link.joint >= 0;
    if (raw == s.on_link) {
      s.link_count = 0;
      continue;
    }
    if (++s.link_count < params_.contact_debounce_ticks) continue;
    s.on_link = raw;
    s.link_count = 0;
    if (raw) {
      Emit(EventType::kLinkContact, f, link.torque_nm,
           kin_.finger(f).name() + " touches with a link, " + link.link +
               " or one further out (" + std::to_string(link.torque_nm) +
               " N m its tip does not explain)");
    } else {
      Emit(EventType::kLinkReleased, f, 0.0,
           kin_.finger(f).name() + "'s links no longer touch");
    }
  }
}

void ManipulationController::ObserveObject(const SensedInput& in,
                                           const std::vector<Eigen::Vector3d>& tips) {
  if (in.effort.size() != in.q.size()) return;
  Eigen::Vector3d tips_force = Eigen::Vector3d::Zero();
  int touching = 0;
  bool on_link = false;
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    const FingerState& s = fingers_[f];
    const SensedTip& tip = in.tips[f];
    on_link = on_link || s.on_link;
    // A link's touch would be read as the tip's friction.
    if (!tip.in_contact || s.on_link) continue;
    const Eigen::Vector3d tangential =
        TipTangentialForce(kin_, f, in.q, in.effort, tip.force, tip.position, in.gravity);
    tips_force += tip.force * NormalFromTip(tips[f], tip.position, 0.0).normal + tangential;
    ++touching;
    if (s.task.role == Role::kExplore) friction_.AddSlide(tip.force, tangential.norm());
  }
  weight_.Update(now_, tips_force, in.gravity, touching >= 3 && !on_link);
  out_.observed_friction = friction_.friction();
  out_.observed_weight_n = weight_.weight();
}

void ManipulationController::ApplyTask(const TaskInput& task,
                                       const std::vector<Eigen::Vector3d>& tips) {
  const bool new_task = task.task_id != task_id_;
  if (new_task) {
    task_id_ = task.task_id;
    motion_done_sent_ = false;
    tracking_error_sent_ = false;
  }
  if (task.has_object_target) {
    if (!has_goal_ || !goal_.isApprox(task.object_target)) motion_done_sent_ = false;
    has_goal_ = true;
    goal_ = task.object_target;
  } else {
    has_goal_ = false;
    has_reference_ = false;
  }
  max_linear_ = task.max_linear_speed > 0 ? task.max_linear_speed : params_.max_linear_speed;
  max_angular_ = task.max_angular_speed > 0 ? task.max_angular_speed : params_.max_angular_speed;
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    FingerState& s = fingers_[f];
    const FingerTask next = f < static_cast<int>(task.fingers.size()) ? task.fingers[f] : FingerTask{};
    const bool primitive_changed = next.primitive != s.task.primitive;
    if (primitive_changed || next.role != s.task.role ||
        (next.has_target && (!s.task.has_target || !next.target.isApprox(s.task.target)))) {
      s.reached = false;
    }
    if (primitive_changed || next.role != s.task.role) {
      s.anchored = false;
      // Ramp only between the two force-controlled primitives (grip <-> explore); a finger
      // that starts pressing from position control gets its force at once.
      const auto forced = [](Primitive p) {
        return p == Primitive::kComposite || p == Primitive::kHybrid;
      };
      s.ramp_since = forced(s.task.primitive) && forced(next.primitive) ? now_ : -1.0;
      s.ramp_from = s.desired;
      // Who grips changed: the grasp has to prove itself stable again.
      stable_sent_ = false;
      stable_since_ = -1.0;
    }
    if (primitive_changed) {
      if (next.primitive == Primitive::kPosition || next.primitive == Primitive::kHold) {
        s.integral = 0.0;
        // Start the finger's own trajectory where its tip is.
        s.target = tips[f];
        s.has_target = true;
      }
    }
    s.task = next;
  }
}

Eigen::Vector3d ManipulationController::LearnLoad(const SensedInput& in,
                                                  const std::vector<Eigen::Vector3d>& tips,
                                                  const std::vector<bool>& in_grip,
                                                  int grip_contacts) {
  // How the object sits in the fingertips: the grip contacts' mean offset from their tip
  // centres. An object sliding down through the grip moves every contact down its tip (by
  // r_tip / (r_tip + r_object) of the slide), which the tactile sensors measure more precisely
  // than the camera sees the object move; but a held object mostly does not slide: the fingers
  // give with it (measured: 0.04 mm on the tips for a 1.1 mm sink). A change of who grips
  // restarts it.
  Eigen::Vector3d seat = Eigen::Vector3d::Zero();
  int grip_set = 0;
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    if (!in_grip[f]) continue;
    seat += in.tips[f].position - tips[f];
    grip_set |= 1 << f;
  }
  if (grip_contacts > 0) seat /= grip_contacts;
  const bool same_grip = grip_set == last_grip_set_;
  last_grip_set_ = grip_set;
  const Eigen::Vector3d carry = load_.Update(dt_, seat, gravity_, grip_contacts >= 2 && same_grip);
  return carry;
}

// A grip finger's anchor leads its tip by at most max_anchor_offset_m, but against gravity by
// as much more as the object has sunk below its reference (`sink_m`), up to carry_offset_m: the
// weight rides on the grip fingers' tangential forces, and a finger's servo gives them only as
// far as its target leads its tip (a 150 g object palm down sank 1.2 cm out of a grip held 4 mm
// behind it, and dropped: docs/benchmarks.md). An object that has not sunk gets no more room
// (with room it did not need, the anchors' wander cost random goals on the nominal sphere).
Eigen::Vector3d ManipulationController::ClampAnchorOffset(const Eigen::Vector3d& offset,
                                                          double sink_m) const {
  const double room = std::min(params_.carry_offset_m,
                               params_.max_anchor_offset_m + std::max(0.0, sink_m));
  if (room <= params_.max_anchor_offset_m) return ClampNorm(offset, params_.max_anchor_offset_m);
  const Eigen::Vector3d up = -gravity_;
  const double along = offset.dot(up);
  const Eigen::Vector3d across =
      ClampNorm(Eigen::Vector3d(offset - along * up), params_.max_anchor_offset_m);
  return across + std::clamp(along, -params_.max_anchor_offset_m, room) * up;
}

double ManipulationController::Ramp(const FingerState& s, double role_force) const {
  if (s.ramp_since < 0 || params_.role_change_s <= 0) return role_force;
  const double a = std::clamp((now_ - s.ramp_since) / params_.role_change_s, 0.0, 1.0);
  return s.ramp_from + a * (role_force - s.ramp_from);
}

double ManipulationController::ForceTerm(FingerState* s, const ForceGains& g, double desired,
                                         double measured) {
  const double e = desired - measured;
  s->integral = std::clamp(s->integral + g.ki * e * dt_, -g.integral_limit, g.integral_limit);
  return std::clamp(g.kp * e + s->integral, -g.integral_limit, g.integral_limit);
}

// One control cycle, in phases: read the sensors, take the task, move the object reference,
// plan the grip forces, run each finger's primitive, say what happened.
const ControllerOutput& ManipulationController::Step(const SensedInput& raw,
                                                     const TaskInput& task) {
  out_.events.clear();
  out_.seq = raw.seq;
  const SensedInput in = UndoTactileCalibration(raw);
  std::string why;
  if (!Validate(in, &why)) {
    Emit(EventType::kInputRejected, -1, 0.0, why + "; holding the last targets");
    return out_;
  }
  AdvanceClock(in.time_s);
  const std::vector<Eigen::Vector3d> tips = TipPositions(in.q);
  UpdateContacts(in);
  DetectLinkContacts(in, tips);
  const SensedInput located = LocateContacts(in, tips);
  UpdateGravity(in);
  UpdateObjectEstimate(in);
  ApplyTask(task, tips);
  ObserveObject(in, tips);
  out_.task_id = task_id_;

  const Eigen::Isometry3d reference_step = AdvanceReference();
  const bool moving = has_goal_ && has_reference_;
  out_.tracking_error_rad = moving ? AngleBetween(estimate_.linear(), reference_.linear()) : 0.0;
  out_.tracking_error_m =
      moving ? (estimate_.translation() - reference_.translation()).norm() : 0.0;
  const GripPlan grip = PlanGrip(located, tips, moving);
  // The position planner: where each tip goes if it moves rigidly with the object (eq. 1-2).
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (moving) motion = ObjectMotion(estimate_, reference_);
  const ObjectMotionStep object{moving, reference_step, motion};

  for (int f = 0; f < kin_.num_fingers(); ++f) {
    FingerState& s = fingers_[f];
    FingerOutput& o = out_.fingers[f];
    o.role = s.task.role;
    o.primitive = s.task.primitive;
    o.tip = tips[f];
    o.tip_axis = tip_axes_[f];
    o.in_contact = s.contact;
    o.force = in.tips[f].force;
    o.contact = in.tips[f].position;
    o.approach = TipApproach(f, located.tips[f].position, tips[f]);
    o.desired_force = 0.0;
    o.track = true;
    switch (s.task.primitive) {
      case Primitive::kHold:
        break;
      case Primitive::kPosition:
        StepPosition(f, tips[f]);
        break;
      case Primitive::kComposite:
        o.desired_force = StepComposite(f, located.tips[f], tips[f], grip, object);
        break;
      case Primitive::kHybrid:
        o.desired_force = StepHybrid(f, located.tips[f], tips[f], grip.centre);
        break;
    }
    o.target = s.target;
    s.desired = o.desired_force;
  }
  EmitGraspEvents(now_, grip.grip_contacts);
  EmitMotionEvents(moving);
  out_.object_estimate = estimate_;
  return out_;
}

// The tactile calibration, if any: undo the sensors' scale, bias and offset.
SensedInput ManipulationController::UndoTactileCalibration(const SensedInput& raw) const {
  SensedInput in = raw;
  const Eigen::Vector3d offset(params_.tactile_position_offset[0],
                               params_.tactile_position_offset[1],
                               params_.tactile_position_offset[2]);
  for (auto& t : in.tips) {
    if (!t.in_contact) continue;
    t.force = std::max(0.0, (t.force - params_.tactile_force_bias) / params_.tactile_force_scale);
    t.position -= offset;
  }
  return in;
}

// A finger that touches and is asked to (by the supervisor: FingerTask::face_surface; an
// explorer by tip_front_explorer; every grip finger by tip_front_grip_fingers): its tip should
// point into the object at its contact (the IK turns the tip's axis that way with its
// redundancy), so that it presses with its front and not with the side beside its distal link.
Eigen::Vector3d ManipulationController::TipApproach(int f, const Eigen::Vector3d& contact,
                                                    const Eigen::Vector3d& tip) const {
  const FingerState& s = fingers_[f];
  const bool exploring = s.task.primitive == Primitive::kHybrid;
  const Eigen::Vector3d into = contact - tip;
  const double distance = into.norm();
  const bool asked = s.task.face_surface || params_.tip_front_grip_fingers ||
                     (exploring && params_.tip_front_explorer);
  if (!s.contact || !asked || !(distance > 1e-3)) {
    return Eigen::Vector3d::Zero();
  }
  return into / distance;
}

// This tick's slide of a touching fingertip's contact toward the finger's base (along the
// surface: the tangent-plane part of minus the tip's axis), when the contact lies further round
// the tip than tip_contact_max_angle_rad: the surface's normal turns toward the way the contact
// slides (on a convex object), and so back toward the tip's front.
Eigen::Vector3d ManipulationController::FrontSlide(int f, const Eigen::Vector3d& contact,
                                                   const Eigen::Vector3d& tip) const {
  const double most = params_.tip_contact_max_angle_rad;
  const Eigen::Vector3d into = contact - tip;
  if (most <= 0 || into.norm() < 1e-3) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d normal = into.normalized();
  const Eigen::Vector3d& axis = tip_axes_[f];
  const double beyond = std::acos(std::clamp(axis.dot(normal), -1.0, 1.0)) - most;
  if (beyond <= 0) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d back = -axis + axis.dot(normal) * normal;  // -axis in the tangent plane
  if (back.norm() < 1e-6) return Eigen::Vector3d::Zero();
  // Full speed 0.2 rad past the angle.
  const double speed = params_.tip_contact_slide_speed * std::min(beyond / 0.2, 1.0);
  return speed * dt_ * back.normalized();
}

// The tick length from the sensed clock (the simulator's, in lockstep), else the nominal one.
// The controller's own clock (role ramps, grip adaptation, how long a grasp has been stable)
// does not count a gap in the sensed one (SensedClock): nothing it measures over time is taken
// as having held through time it did not see.
void ManipulationController::AdvanceClock(double time_s) {
  const SensedClock::Advanced advanced = clock_.Advance(time_s);
  if (advanced.step_s > 0) dt_ = advanced.step_s;
  now_ = clock_.now();
}

// Where the fingertips are (forward kinematics); a finger without a target yet holds there.
std::vector<Eigen::Vector3d> ManipulationController::TipPositions(const std::vector<double>& q) {
  const int nf = kin_.num_fingers();
  std::vector<Eigen::Vector3d> tips(nf);
  tip_axes_.resize(nf);
  for (int f = 0; f < nf; ++f) {
    kin_.finger(f).TipFrame(kin_.FingerJoints(f, q), &tips[f], &tip_axes_[f]);
  }
  for (int f = 0; f < nf; ++f) {
    if (!fingers_[f].has_target) {
      fingers_[f].target = tips[f];
      fingers_[f].has_target = true;
    }
  }
  return tips;
}

// Where each finger touches the object, as far as the controller can tell: the sensed point
// while the sensor reads a contact, the last one (moved with the tip) while a lost reading is
// being debounced, else the tip centre. A sensor without contact reports no point (zeros): it
// must never be taken for one, or an explorer's normal and the grip's directions aim at the
// palm's origin.
SensedInput ManipulationController::LocateContacts(const SensedInput& in,
                                                   const std::vector<Eigen::Vector3d>& tips) {
  SensedInput located = in;
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    FingerState& s = fingers_[f];
    Eigen::Vector3d& point = located.tips[f].position;
    if (in.tips[f].in_contact && in.tips[f].force > params_.contact_threshold_n) {
      s.contact_offset = point - tips[f];
      s.has_contact_offset = true;
    } else if (s.contact && s.has_contact_offset) {
      point = tips[f] + s.contact_offset;
    } else {
      if (!s.contact) s.has_contact_offset = false;
      point = tips[f];
    }
  }
  return located;
}

// The object reference: small steps of bounded speed toward the goal (Fig. 1). Returns its
// motion this tick, in the palm frame, which carries the grip fingers' anchors along
// (feedforward).
Eigen::Isometry3d ManipulationController::AdvanceReference() {
  Eigen::Isometry3d reference_step = Eigen::Isometry3d::Identity();
  if (has_goal_ && has_estimate_) {
    if (!has_reference_) {
      reference_ = estimate_;
      has_reference_ = true;
    }
    const Eigen::Isometry3d previous = reference_;
    reference_ = StepToward(reference_, goal_, max_linear_ * dt_, max_angular_ * dt_);
    reference_step = reference_ * previous.inverse();
  }
  return reference_step;
}

// The force plan over the grip fingers that touch the object.
ManipulationController::GripPlan ManipulationController::PlanGrip(
    const SensedInput& in, const std::vector<Eigen::Vector3d>& tips, bool moving) {
  const int nf = kin_.num_fingers();
  GripPlan g;
  g.contacts.resize(nf);
  g.in_grip.assign(nf, false);
  for (int f = 0; f < nf; ++f) {
    g.contacts[f] = in.tips[f].position;  // located: the tip centre where nothing touches
    g.in_grip[f] = fingers_[f].task.role == Role::kGrip &&
                   fingers_[f].task.primitive == Primitive::kComposite && fingers_[f].contact;
  }
  const std::vector<Eigen::Vector3d>& contacts = g.contacts;
  const std::vector<bool>& in_grip = g.in_grip;
  // Exploring fingers push lightly along their contact normals; that push is known, so the grip
  // forces cancel it too.
  Eigen::Vector3d external = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> normals(nf, Eigen::Vector3d::Zero());
  for (int f = 0; f < nf; ++f) {
    const FingerState& s = fingers_[f];
    if (s.contact) normals[f] = (in.tips[f].position - tips[f]).normalized();
    if (s.task.primitive == Primitive::kHybrid && s.contact && normals[f].allFinite()) {
      const double force = s.task.force_n > 0 ? s.task.force_n : params_.explore_force_n;
      external += Ramp(s, force) * normals[f];
    }
  }
  g.grip_contacts = static_cast<int>(std::count(in_grip.begin(), in_grip.end(), true));
  const int grip_contacts = g.grip_contacts;
  // Along a grip force the force loop wins over any position correction, so the object's
  // translation is corrected through the force plan itself: the grip forces add up to a net
  // force toward the reference instead of zero (a spring on the object's position).
  if (moving && has_estimate_) {
    const Eigen::Vector3d error = reference_.translation() - estimate_.translation();
    external -= ClampNorm(params_.translation_force_gain * error, params_.max_translation_force_n);
  }
  std::optional<Eigen::Vector3d> aim;
  if (params_.use_surface_centre && has_estimate_) {
    aim = estimate_.translation() + Eigen::Vector3d(params_.surface_centre_offset[0],
                                                    params_.surface_centre_offset[1],
                                                    params_.surface_centre_offset[2]);
  }
  AdaptGrip(in, tips, in_grip, grip_contacts);
  DetectSink(tips, in_grip);
  const double grip_force = grip_.grip_force();
  g.grip_force = grip_force;
  out_.grip_force_n = grip_force;
  out_.load_scale = grip_.load_scale();
  // The minimum scales with the grip (the ratio first: 1.0 exactly when nothing adapted).
  const double minimum = params_.min_grip_force_n * (grip_force / params_.grip_force_n);
  // The load the grip has learned to carry (load_estimator.h): added to what the grip forces
  // must add up to, and squeezed for where friction must carry it.
  const double max_force = std::max(params_.normals_aim.max_force_n, grip_force);
  double squeeze = grip_force;
  if (params_.load.enabled) {
    const Eigen::Vector3d carry = LearnLoad(in, tips, in_grip, grip_contacts);
    external -= carry;
    if (grip_contacts >= 2 && params_.load.friction_assumed > 0) {
      squeeze = std::min(std::max(grip_force, carry.norm() / (grip_contacts *
                                                            params_.load.friction_assumed)),
                         max_force);
    }
  }
  // What the contacts' pushes hold up now, read from the tactile sensors: where friction cannot
  // carry the weight, the pushes below carry it and this reads it; the bounded plan then keeps
  // holding it (low-passed: an explore's jolt is not a weight). Only once the palm (its normal,
  // the palm frame's x) faces away from up: palm up the palm cradles the object and the level
  // contacts' friction carries it, and the plan is the one of before. At least the angle: 0 is
  // every orientation, palm up too.
  const bool balance_gravity =
      params_.normals_aim.enabled && params_.normals_aim.friction_along_gravity > 0 &&
      -gravity_.x() <= std::cos(params_.normals_aim.gravity_balance_from_rad);
  if (balance_gravity) {
    double held = 0.0;
    for (int f = 0; f < nf; ++f) {
      if (fingers_[f].contact && normals[f].allFinite()) {
        held += in.tips[f].force * normals[f].dot(-gravity_);
      }
    }
    const double a = dt_ / (params_.normals_aim.held_time_constant_s + dt_);
    held_n_ += a * (std::clamp(held, 0.0, params_.normals_aim.max_force_n) - held_n_);
  }
  const FrictionShare share{
      params_.normals_aim.friction_share_n,
      balance_gravity ? params_.normals_aim.friction_along_gravity : 0.0,
      params_.normals_aim.level_push_sine};
  std::optional<ForcePlan> bounded;
  if (params_.normals_aim.enabled && !aim && grip_contacts >= params_.normals_aim.min_contacts) {
    // Where the lines leave the point free: the estimate, else the grip contacts' centroid.
    Eigen::Vector3d fallback = Eigen::Vector3d::Zero();
    if (has_estimate_) {
      fallback = estimate_.translation();
    } else {
      for (int f = 0; f < nf; ++f) fallback += in_grip[f] ? contacts[f] : Eigen::Vector3d::Zero();
      fallback /= grip_contacts;
    }
    if (const auto meet = NormalsMeetingPoint(contacts, normals, in_grip, fallback)) {
      const std::vector<Eigen::Vector3d> directions = AimWithinCones(
          contacts, normals, in_grip, *meet, params_.normals_aim.max_off_normal_rad);
      bounded = PlanBoundedForcesAlong(directions, in_grip, *meet, squeeze,
                                       std::min(minimum, params_.explore_force_n), max_force,
                                       -external - (balance_gravity ? held_n_ : 0.0) * gravity_,
                                       params_.normals_aim.balance_weight, gravity_, share);
    }
  }
  const double squeezed_minimum = minimum * (squeeze / grip_force);
  g.plan = bounded ? *bounded
                   : PlanGripForces(contacts, in_grip, squeeze, squeezed_minimum, external, aim);
  // Where the object is, as far as the fingers can tell: the grip centroid, else the estimate;
  // a centroid far out where skew normals meet is no place to look for it.
  g.centre = grip_contacts >= 2 ? g.plan.centroid
                                : (has_estimate_ ? Eigen::Vector3d(estimate_.translation())
                                                 : Eigen::Vector3d::Zero());
  if (grip_contacts >= 2 && has_estimate_) {
    g.centre = CentreWithinReach(g.centre, estimate_.translation(), contacts, in_grip);
  }
  out_.contact_centroid = g.centre;
  return g;
}

// The grip adapts to the load: the explorer's share and what slips taught (grip_adapter.h).
void ManipulationController::AdaptGrip(const SensedInput& in,
                                       const std::vector<Eigen::Vector3d>& tips,
                                       const std::vector<bool>& in_grip, int grip_contacts) {
  if (!params_.grip_adaptation.enabled) return;
  const int nf = kin_.num_fingers();
  std::vector<std::optional<Eigen::Vector3d>> offsets(nf);
  int holding = 0;
  for (int f = 0; f < nf; ++f) {
    if (in_grip[f]) offsets[f] = in.tips[f].position - tips[f];
    const FingerState& s = fingers_[f];
    holding += (s.task.role == Role::kGrip && s.task.primitive == Primitive::kComposite) ||
               (s.task.role == Role::kExplore && s.task.primitive == Primitive::kHybrid);
  }
  if (grip_.Update(now_, offsets, grip_contacts, holding)) {
    Emit(EventType::kSlip, -1, grip_.load_scale(),
         "slip at " + std::to_string(grip_.slip_speed()) + " m/s: grip raised to " +
             std::to_string(grip_.grip_force()) + " N");
  }
}

void ManipulationController::DetectSink(const std::vector<Eigen::Vector3d>& tips,
                                        const std::vector<bool>& in_grip) {
  if (!params_.sink_detector.enabled) return;
  std::vector<std::optional<Eigen::Vector3d>> grip_tips(tips.size());
  bool exploring = false;
  for (size_t f = 0; f < tips.size(); ++f) {
    if (in_grip[f]) grip_tips[f] = tips[f];
    exploring = exploring || fingers_[f].task.role == Role::kExplore;
  }
  if (sink_.Update(now_, grip_tips, gravity_, exploring)) {
    Emit(EventType::kSinking, -1, sink_.speed(),
         "the grip sinks along gravity at " + std::to_string(1e3 * sink_.speed()) + " mm/s");
  }
}

// POSITION: the target moves toward the task's point at bounded speed.
void ManipulationController::StepPosition(int f, const Eigen::Vector3d& tip) {
  FingerState& s = fingers_[f];
  if (!s.task.has_target) return;
  s.target += ClampNorm(s.task.target - s.target, params_.approach_speed * dt_);
  if (!s.reached && (tip - s.task.target).norm() < params_.target_tolerance_m) {
    s.reached = true;
    Emit(EventType::kTargetReached, f, 0.0, kin_.finger(f).name() + " reached its point");
  }
}

// COMPOSITE: P/PI on position (the object's motion) plus PI on force along the plan's
// direction, summed into one target. Returns the force asked.
double ManipulationController::StepComposite(int f, const SensedTip& sensed,
                                             const Eigen::Vector3d& tip, const GripPlan& grip,
                                             const ObjectMotionStep& object) {
  FingerState& s = fingers_[f];
  // Position. The finger is anchored where it took hold: a grip needs the servo's stiffness
  // in every direction, or the tangential part of the planned force rolls the tip away.
  // The anchor moves rigidly with the object reference (feedforward); the displacement the
  // position planner asks of this contact (eq. 1-2, estimate -> reference) corrects it: P
  // now, and I into the anchor, which removes the steady error of rolling contacts (a
  // rolling object turns (r_object + r_tip) / r_object times as far as its fingertips).
  if (!s.anchored) {
    s.anchor = tip;
    s.anchored = true;
  }
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  if (object.moving && s.task.role == Role::kGrip) {
    // Rolling: a fingertip that rolls on the object turns about its centre by
    // |contact - centre| / |tip - centre| of the object's turn (both seen, not known).
    double roll = 1.0;
    if (s.contact && params_.rolling_feedforward) {
      const double rc = (sensed.position - estimate_.translation()).norm();
      const double rt = (tip - estimate_.translation()).norm();
      if (rt > 1e-6) roll = std::clamp(rc / rt, 0.3, 1.0);
    }
    const Eigen::AngleAxisd turn(object.reference_step.linear());
    Eigen::Isometry3d rolled = Eigen::Isometry3d::Identity();
    rolled.linear() = Eigen::AngleAxisd(roll * turn.angle(), turn.axis()).toRotationMatrix();
    rolled.translation() = object.reference_step.translation() + reference_.translation() -
                           rolled.linear() * reference_.translation();
    s.anchor = rolled * s.anchor;
    const Eigen::Vector3d error = MoveWithObject(estimate_, object.motion, tip) - tip;
    const Eigen::Vector3d translation = reference_.translation() - estimate_.translation();
    const Eigen::Vector3d rotation = error - translation;
    s.anchor += dt_ * (params_.position_integral_gain * rotation +
                       params_.translation_integral_gain * translation);
    displacement = params_.position_gain * rotation + params_.translation_gain * translation;
  }
  // Force: PI along the planned direction (toward the grip centroid).
  Eigen::Vector3d direction = grip.plan.forces[f].direction;
  double desired = grip.plan.forces[f].magnitude;
  if (!grip.in_grip[f]) {
    // Not (yet) part of the balance: push toward the object to (re)gain contact.
    direction = grip.centre - grip.contacts[f];
    desired = s.task.role == Role::kGrip ? grip.grip_force : params_.explore_force_n;
  }
  if (s.task.force_n > 0) desired = s.task.force_n;
  desired = Ramp(s, desired);
  if (direction.norm() < 1e-9) direction = s.last_direction;
  direction.normalize();
  if (!direction.allFinite()) direction.setZero();
  s.last_direction = direction;
  if (!s.contact && params_.guarded_approach_lead_m > 0) {
    // No contact: a guarded move toward the object; the force loop waits for a contact.
    s.integral = 0.0;
    s.anchor = tip;
    s.target = tip + params_.guarded_approach_lead_m * direction;
    return desired;
  }
  if (s.contact && params_.tip_front_grip_fingers) {
    s.anchor += FrontSlide(f, sensed.position, tip);
  }
  // How far the object has sunk below where the task holds it (0 without a reference).
  const double sink = object.moving ? (reference_.translation() - estimate_.translation())
                                          .dot(-gravity_)
                                    : 0.0;
  s.anchor = tip + ClampAnchorOffset(s.anchor - tip, sink);
  s.target = s.anchor + displacement +
             direction * ForceTerm(&s, params_.force, desired, sensed.force);
  return desired;
}

// HYBRID: position in the contact's tangent plane toward the task's point, force along its
// normal. Returns the force asked.
double ManipulationController::StepHybrid(int f, const SensedTip& sensed,
                                          const Eigen::Vector3d& tip,
                                          const Eigen::Vector3d& centre) {
  FingerState& s = fingers_[f];
  // The normal into the object: from the tip centre through the contact point; without
  // contact, toward the object.
  Eigen::Vector3d normal = s.contact ? Eigen::Vector3d(sensed.position - tip)
                                     : Eigen::Vector3d(centre - tip);
  if (normal.norm() < 1e-9) normal = s.last_direction;
  normal.normalize();
  if (!normal.allFinite()) normal.setZero();
  s.last_direction = normal;
  // Anchored like a grip finger, but only in the tangent plane: the anchor slides toward
  // the target point; along the normal it follows the measured tip, and the force PI sets
  // how far in the target lies.
  if (!s.anchored) {
    s.anchor = tip;
    s.anchored = true;
  }
  s.anchor -= normal * (s.anchor - tip).dot(normal);
  Eigen::Vector3d tangential = Eigen::Vector3d::Zero();
  if (s.task.has_target) {
    const Eigen::Vector3d to_goal = s.task.target - s.anchor;
    const Eigen::Vector3d in_plane = to_goal - to_goal.dot(normal) * normal;
    tangential = ClampNorm(params_.hybrid_tangential_gain * dt_ * in_plane,
                           params_.hybrid_max_speed * dt_);
    if (!s.reached && in_plane.norm() < params_.target_tolerance_m) {
      s.reached = true;
      Emit(EventType::kTargetReached, f, 0.0, kin_.finger(f).name() + " reached its point");
    }
  }
  const double desired = Ramp(s, s.task.force_n > 0 ? s.task.force_n : params_.explore_force_n);
  s.anchor += tangential;
  if (s.contact) s.anchor += FrontSlide(f, sensed.position, tip);
  s.target = s.anchor + normal * ForceTerm(&s, params_.explore_force, desired, sensed.force);
  return desired;
}

// GRASP_STABLE once every grip finger has held its force for stable_hold_s; GRASP_LOST when
// fewer than two grip contacts remain.
void ManipulationController::EmitGraspEvents(double time_s, int grip_contacts) {
  int grip_assigned = 0;
  bool stable = true;
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    const FingerState& s = fingers_[f];
    if (s.task.role != Role::kGrip || s.task.primitive != Primitive::kComposite) continue;
    ++grip_assigned;
    const FingerOutput& o = out_.fingers[f];
    if (!s.contact ||
        std::abs(o.force - o.desired_force) > params_.stable_force_tolerance * o.desired_force) {
      stable = false;
    }
  }
  stable = stable && grip_assigned >= 2;
  if (stable) {
    if (stable_since_ < 0) stable_since_ = time_s;
    if (!stable_sent_ && time_s - stable_since_ >= params_.stable_hold_s) {
      stable_sent_ = true;
      Emit(EventType::kGraspStable, -1, time_s - stable_since_, "grasp stable");
    }
  } else {
    stable_since_ = -1.0;
    stable_sent_ = false;
  }
  out_.grasp_stable = stable_sent_;
  if (grip_assigned >= 2 && grip_contacts < 2) {
    if (!grasp_lost_sent_) {
      grasp_lost_sent_ = true;
      Emit(EventType::kGraspLost, -1, grip_contacts, "fewer than two grip contacts");
    }
  } else if (grip_contacts >= 2) {
    grasp_lost_sent_ = false;
  }
}

// TRACKING_ERROR when the object lags its reference; MOTION_DONE when it is at its goal.
void ManipulationController::EmitMotionEvents(bool moving) {
  if (!moving) {
    out_.motion_done = false;
    return;
  }
  if (out_.tracking_error_rad > params_.tracking_error_rad && !tracking_error_sent_) {
    tracking_error_sent_ = true;
    Emit(EventType::kTrackingError, -1, out_.tracking_error_rad, "object lags its reference");
  } else if (out_.tracking_error_rad < 0.5 * params_.tracking_error_rad) {
    tracking_error_sent_ = false;
  }
  const bool reference_at_goal = AngleBetween(reference_.linear(), goal_.linear()) < 1e-9 &&
                                 (reference_.translation() - goal_.translation()).norm() < 1e-9;
  out_.motion_done = reference_at_goal &&
                     AngleBetween(estimate_.linear(), goal_.linear()) < params_.motion_done_rad &&
                     (estimate_.translation() - goal_.translation()).norm() < params_.motion_done_m;
  if (out_.motion_done && !motion_done_sent_) {
    motion_done_sent_ = true;
    Emit(EventType::kMotionDone, -1, out_.tracking_error_rad, "object at its goal");
  }
}

}  // namespace dmpl
