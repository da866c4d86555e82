#pragma once
#include <array>

#include "components/controller/friction_observer.h"
#include "components/controller/grip_adapter.h"
#include "components/controller/weight_observer.h"
#include "components/controller/load_estimator.h"
#include "components/controller/sink_detector.h"
#include "components/runtime/params.h"

namespace dmpl {

// PI on the force error along the contact direction; output is a tip displacement (m).
struct ForceGains {
  double kp = 0.001;              // m/N
  double ki = 0.03;               // m/(N s)
  double integral_limit = 0.015;  // m: anti-windup (the force term never pushes further than this)
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(kp), AtLeast(0));
    a->Visit(DMPL_NVP(ki), AtLeast(0));
    a->Visit(DMPL_NVP(integral_limit), Above(0));
  }
};

// Grip forces aimed where the grip contacts' normals meet (the centre of a sphere, the axis of a
// cylinder; force_planner.h: NormalsMeetingPoint, PlanBoundedForces) instead of at the contacts'
// centroid (the paper). Along the normals a squeeze needs no friction, so it can be raised on a
// slick object without pushing it out; a finger whose opposite explores is kept light
// (explore_force_n) instead of pushing the object sideways, and friction carries what cannot be
// balanced (balance_weight), as well as the object's weight (never balanced along gravity,
// where contacts that sank above the equator would otherwise ease the squeeze).
struct NormalsAimParams {
  bool enabled = false;
  int min_contacts = 2;          // grip contacts needed
  double balance_weight = 10.0;  // an unbalanced newton against a newton off the nominal squeeze
  double max_force_n = 2.5;      // per finger: what the servos hold
  // N per axis the grip forces' sum may stray from the balance, left to friction (0: none):
  // a pair slightly off facing each other keeps its squeeze instead of both being eased.
  double friction_share_n = 0.0;
  // With this > 0 (a friction coefficient) the grip forces add up along gravity to what the
  // tips' pushes held up (the tactile forces along their normals, low-passed), within what the
  // contacts' friction carries there, instead of leaving all of it to friction: a finger on top
  // pushing down is eased, or the one below pushes up for it, when the others cannot hold the
  // weight by friction. A steep push's friction counts this coefficient times its push.
  double friction_along_gravity = 0.0;
  double held_time_constant_s = 0.1;  // s: the low-pass of what the pushes held up
  double level_push_sine = 0.7;  // a push within asin(this) of level carries its own part
  // Only once the palm's normal is at least this far from up (rad; 0: always): palm up the palm
  // cradles the object and the level contacts' friction carries it (measured:
  // docs/benchmarks.md, stop 42).
  double gravity_balance_from_rad = 0.7853981633974483;
  // A grip force leans at most this far from its contact's normal toward where the normals meet
  // (rad; pi: never clamped): a tip pushes within its friction cone or slides, and where the
  // normals do not meet in the object (a pinch across a capsule's side, a push on its cap) the
  // aim lies behind a contact (force_planner.h: AimWithinCones). 0.35 rad is the cone of
  // friction 0.36, below the slickest object benchmarked (0.4); on a sphere nothing is clamped.
  double max_off_normal_rad = 0.35;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(enabled));
    a->Visit(DMPL_NVP(min_contacts), AtLeast(2));
    a->Visit(DMPL_NVP(balance_weight), Above(0));
    a->Visit(DMPL_NVP(max_force_n));
    a->Visit(DMPL_NVP(friction_share_n), AtLeast(0));
    a->Visit(DMPL_NVP(friction_along_gravity), AtLeast(0));
    a->Visit(DMPL_NVP(held_time_constant_s), AtLeast(0));
    a->Visit(DMPL_NVP(level_push_sine), InRange(0, 1));
    a->Visit(DMPL_NVP(gravity_balance_from_rad), InRange(0, 3.141592653589793));
    a->Visit(DMPL_NVP(max_off_normal_rad), InRange(0, 3.141592653589793));
  }
};

// Section `controller.node`: the controller node's exchange with the supervisor, apart from the
// control itself.
struct ControllerNodeParams {
  bool wait_for_task = true;  // lockstep: tick k waits for the supervisor's answer to k - 1
  // The supervisor's period: every this many ticks the controller reports (DMPL_CONTROLLER_REPORT,
  // with the events since the last report) and the supervisor answers; a task takes effect the
  // tick after the report it answers. Its full status goes out every tick all the same.
  int report_period_ticks = 10;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(wait_for_task));
    a->Visit(DMPL_NVP(report_period_ticks), InRange(1, 1000));
  }
};

// Section `controller`. Gains are hand-set defaults; tools/dmpl calibrate can fit them.
struct ControllerParams {
  // Position planner (equations 1-2) and the object reference (Fig. 1).
  // The contact displacement of eq. 2 splits exactly into the object's rotation about its centre
  // and its translation. The orientation estimate is clean; the position carries the camera's
  // noise (0.5 cm in the paper), which a stiff finger would turn straight into force noise: the
  // translation gets the lower gains.
  double position_gain = 1.0;            // P on the rotation part: share applied at once
  double position_integral_gain = 5.0;   // I on the rotation part: 1/s, into the finger's anchor
  double translation_gain = 0.2;         // P on the translation part
  double translation_integral_gain = 1.0;  // I on the translation part, 1/s
  double max_anchor_offset_m = 0.004;    // how far a grip finger's anchor may lead its tip
  double carry_offset_m = 0.0;           // ... against gravity, as the object sinks (if more)
  double translation_force_gain = 0.0;   // N/m: net grip force per metre of position error
  double max_translation_force_n = 0.4;
  bool rolling_feedforward = false;      // anchors turn by the rolling ratio, not rigidly
  double max_linear_speed = 0.01;        // m/s of the object reference
  double max_angular_speed = 0.25;       // rad/s of the object reference
  double object_position_time_constant_s = 0.1;   // low-pass of the noisy object position
  double object_orientation_time_constant_s = 0.005;
  // Force planner.
  double grip_force_n = 0.8;             // nominal normal force of a grip finger
  double min_grip_force_n = 0.4;
  double explore_force_n = 0.1;          // exploration finger (the paper's 0.1 N)
  double role_change_s = 0.3;            // a finger's desired force ramps to its new role's
  GripAdaptationParams grip_adaptation;  // the grip raised for the explorer's share and on slip
  NormalsAimParams normals_aim;          // grip forces along the contact normals
  LoadParams load;                       // the load the grip learns to carry (load_estimator.h)
  FrictionObserverParams friction_observer;  // the friction the explorers' slides show
  WeightObserverParams weight_observer;      // the weight the tips' forces carry
  SinkDetectorParams sink_detector;          // the object sinking out of the grip
  // Gravity's direction comes from the palm's IMU (SensedInput::gravity), low-passed with this
  // time constant; the object's weight is not known.
  double gravity_time_constant_s = 0.02;
  ForceGains force;                      // grip fingers (composite)
  ForceGains explore_force{0.002, 0.15, 0.015};  // exploration (hybrid): a light touch must
                                                 // follow the object's small motions closely
  // Hybrid control (exploration): tangential motion toward the finger's target point.
  double hybrid_tangential_gain = 2.0;   // 1/s
  double hybrid_max_speed = 0.02;        // m/s
  // A grip finger that has lost its contact (or not yet found it) approaches the object by a
  // guarded move: its target leads its tip by this toward the object until the tactile sensor
  // reports contact, so that a finger stopped by something other than its tactile tip (a
  // phalanx against the object's body, another finger) presses lightly instead of with the
  // force loop's whole wound-up reach (force.integral_limit). 0: the force loop's push.
  double guarded_approach_lead_m = 0.0;
  // Finger position control (approach without contact).
  double approach_speed = 0.03;          // m/s
  double target_tolerance_m = 0.002;
  // Contacts and events.
  double contact_threshold_n = 0.03;     // sensed force above which a fingertip touches
  // Joint torque (N m) the tip force does not explain above which a finger touches with a link
  // (LINK_CONTACT events; 0: not checked). The servos' gravity compensation leaves a few
  // hundredths; a link pressed on the object, tenths (docs/benchmarks.md).
  double link_contact_torque_nm = 0.15;
  // The friction at a fingertip that may explain torque before it counts as a link contact (a
  // grip carrying the object's weight pushes across the normal too; the tip reads the normal
  // force only).
  double link_contact_friction = 1.5;
  // A fingertip touching further round from its front than this (the angle between the tip's
  // axis and its contact normal) presses the object with the side next to its distal link, and
  // the link touches next; its contact slides toward the finger's base (grip and explore
  // fingers) at up to tip_contact_slide_speed until it is back within the angle (0: off).
  double tip_contact_max_angle_rad = 0.0;
  double tip_contact_slide_speed = 0.01;  // m/s
  // Whether grip fingers too turn their tips toward the object (ik.approach_gain) and slide
  // back toward their bases; else only an exploring finger does, while it looks for its next
  // contact (a grip finger that changes its posture or its contact unsettles the grasp: measured,
  // the initial grasp of long cylinders and capsules and under 3 ticks of sensing delay).
  bool tip_front_grip_fingers = false;
  // Whether an exploring finger turns its tip toward the object whether or not it is asked to
  // (FingerTask::face_surface); false: only the fingers the supervisor asks.
  bool tip_front_explorer = true;
  int contact_debounce_ticks = 5;        // a new contact must persist this long...
  int contact_loss_ticks = 40;           // ...a loss this long (rolling contacts flicker)
  double motion_done_rad = 0.01;         // estimate within this of the goal: motion done
  double motion_done_m = 0.004;
  double tracking_error_rad = 0.15;      // TRACKING_ERROR event above this
  double stable_force_tolerance = 0.35;  // |f - f*| < tol * f* for every grip finger...
  double stable_hold_s = 0.15;           // ...this long: GRASP_STABLE
  ControllerNodeParams node;             // how the node meets the supervisor (not the control)
  // Tactile calibration (tools/dmpl calibrate): force = (sensed - bias) / scale, contact point =
  // sensed - offset.
  double tactile_force_scale = 1.0;
  double tactile_force_bias = 0.0;
  std::array<double, 3> tactile_position_offset = {0.0, 0.0, 0.0};
  // The force planner aims at the contacts' centroid (the paper), or, when use_surface_centre is
  // set, at the object estimate + surface_centre_offset (a surface fitted by calibration).
  bool use_surface_centre = false;
  std::array<double, 3> surface_centre_offset = {0.0, 0.0, 0.0};

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(position_gain), InRange(0, 2));
    a->Visit(DMPL_NVP(position_integral_gain));
    a->Visit(DMPL_NVP(translation_gain));
    a->Visit(DMPL_NVP(translation_integral_gain));
    a->Visit(DMPL_NVP(max_anchor_offset_m));
    a->Visit(DMPL_NVP(carry_offset_m), InRange(0, 0.05));
    a->Visit(DMPL_NVP(translation_force_gain));
    a->Visit(DMPL_NVP(max_translation_force_n));
    a->Visit(DMPL_NVP(rolling_feedforward));
    a->Visit(DMPL_NVP(max_linear_speed), Above(0));
    a->Visit(DMPL_NVP(max_angular_speed), Above(0));
    a->Visit(DMPL_NVP(object_position_time_constant_s), AtLeast(0));
    a->Visit(DMPL_NVP(object_orientation_time_constant_s), AtLeast(0));
    a->Visit(DMPL_NVP(grip_force_n), Above(0));
    a->Visit(DMPL_NVP(min_grip_force_n), AtLeast(0));
    a->Visit(DMPL_NVP(explore_force_n), AtLeast(0));
    a->Visit(DMPL_NVP(role_change_s));
    a->Visit(DMPL_NVP(grip_adaptation));
    a->Visit(DMPL_NVP(normals_aim));
    a->Visit(DMPL_NVP(load));
    a->Visit(DMPL_NVP(friction_observer));
    a->Visit(DMPL_NVP(weight_observer));
    a->Visit(DMPL_NVP(sink_detector));
    a->Visit(DMPL_NVP(gravity_time_constant_s), AtLeast(0));
    a->Visit(DMPL_NVP(force));
    a->Visit(DMPL_NVP(explore_force));
    a->Visit(DMPL_NVP(hybrid_tangential_gain));
    a->Visit(DMPL_NVP(hybrid_max_speed), Above(0));
    a->Visit(DMPL_NVP(guarded_approach_lead_m), InRange(0, 0.02));
    a->Visit(DMPL_NVP(approach_speed), Above(0));
    a->Visit(DMPL_NVP(target_tolerance_m));
    a->Visit(DMPL_NVP(contact_threshold_n));
    a->Visit(DMPL_NVP(link_contact_torque_nm), AtLeast(0));
    a->Visit(DMPL_NVP(link_contact_friction), AtLeast(0));
    a->Visit(DMPL_NVP(tip_contact_max_angle_rad), InRange(0.0, 3.141592653589793));
    a->Visit(DMPL_NVP(tip_contact_slide_speed), AtLeast(0));
    a->Visit(DMPL_NVP(tip_front_grip_fingers));
    a->Visit(DMPL_NVP(tip_front_explorer));
    a->Visit(DMPL_NVP(contact_debounce_ticks), AtLeast(1));
    a->Visit(DMPL_NVP(contact_loss_ticks), AtLeast(1));
    a->Visit(DMPL_NVP(motion_done_rad));
    a->Visit(DMPL_NVP(motion_done_m));
    a->Visit(DMPL_NVP(tracking_error_rad));
    a->Visit(DMPL_NVP(stable_force_tolerance));
    a->Visit(DMPL_NVP(stable_hold_s));
    a->Visit(DMPL_NVP(node));
    a->Visit(DMPL_NVP(tactile_force_scale), Above(0));
    a->Visit(DMPL_NVP(tactile_force_bias));
    a->Visit(DMPL_NVP(tactile_position_offset));
    a->Visit(DMPL_NVP(use_surface_centre));
    a->Visit(DMPL_NVP(surface_centre_offset));
  }
  void Validate(const std::string& source) const;
};

}  // namespace dmpl
