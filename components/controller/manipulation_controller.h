#pragma once
// The local manipulation controller (the paper's Fig. 3) as a pure core: sensed data and the
// current task in, fingertip targets for the IK and events for the supervisor out. It sees only
// what a real hand senses: joint angles, fingertip contact positions and force magnitudes, and a
// noisy object pose. Nothing about the object's shape, size, mass or friction.
//
// Per finger, the DMPL primitives (§III.A):
//  - POSITION: move the tip to a point at bounded speed (approach, no contact expected);
//  - COMPOSITE: P on the position planner's displacement + PI on the force error along the
//    direction to the grip centroid, summed into one tip target;
//  - HYBRID: position in the contact's tangent plane toward a point, force along its normal;
//  - HOLD: keep the current target.
// and the composite manipulation action: a desired object pose, moved by the GRIP fingers.
#include <cstdint>
#include <string>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "components/controller/controller_params.h"
#include "components/controller/controller_types.h"
#include "components/controller/force_planner.h"
#include "components/controller/friction_observer.h"
#include "components/controller/sink_detector.h"
#include "components/controller/weight_observer.h"
#include "components/controller/grip_adapter.h"
#include "components/controller/load_estimator.h"
#include "components/kinematics/hand_kinematics.h"
#include "components/runtime/sensed_clock.h"

namespace dmpl {

class ManipulationController {
 public:
  ManipulationController(const HandKinematics& kinematics, const ControllerParams& params,
                         double tick_s);

  // One control cycle. Bad input (NaN, wrong sizes) is rejected: the last targets are held and
  // an INPUT_REJECTED event says why.
  const ControllerOutput& Step(const SensedInput& raw, const TaskInput& task);

  const ControllerOutput& output() const { return out_; }
  const ControllerParams& params() const { return params_; }

 private:
  struct FingerState {
    FingerTask task;
    bool contact = false;        // debounced
    int contact_count = 0;       // ticks the raw contact has disagreed with `contact`
    bool on_link = false;        // debounced: touches with a link (DetectLinkContacts)
    int link_count = 0;          // ticks the raw link contact has disagreed with `on_link`
    double integral = 0.0;       // force PI integrator (m)
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    bool has_target = false;
    bool reached = false;
    bool anchored = false;       // composite: the anchor is set
    double desired = 0.0;        // the force asked last tick
    double ramp_from = 0.0;      // ...and at the last role change, ramped away from
    double ramp_since = -1.0;
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
    Eigen::Vector3d last_direction = Eigen::Vector3d::Zero();
    // The last sensed contact point relative to the tip centre: while a lost reading is being
    // debounced (`contact` still true, no reading) the contact is taken to be where it was.
    Eigen::Vector3d contact_offset = Eigen::Vector3d::Zero();
    bool has_contact_offset = false;
  };

  // This tick's grip: who grips, where, and the force plan over them.
  struct GripPlan {
    std::vector<Eigen::Vector3d> contacts;  // sensed contact, else the fingertip
    std::vector<bool> in_grip;              // a grip finger in contact
    int grip_contacts = 0;
    double grip_force = 0.0;                // per grip finger, as adapted
    ForcePlan plan;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // where the object is, as the fingers tell
  };
  // This tick's move of the object reference (the position planner's input).
  struct ObjectMotionStep {
    bool moving = false;
    Eigen::Isometry3d reference_step = Eigen::Isometry3d::Identity();  // palm frame
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();          // M = O^-1 O'
  };

  // The phases of Step, in order.
  SensedInput UndoTactileCalibration(const SensedInput& raw) const;
  bool Validate(const SensedInput& in, std::string* why) const;
  Eigen::Vector3d FrontSlide(int f, const Eigen::Vector3d& contact,
                             const Eigen::Vector3d& tip) const;
  Eigen::Vector3d TipApproach(int f, const Eigen::Vector3d& contact,
                              const Eigen::Vector3d& tip) const;
  void AdvanceClock(double time_s);
  std::vector<Eigen::Vector3d> TipPositions(const std::vector<double>& q);
  SensedInput LocateContacts(const SensedInput& in, const std::vector<Eigen::Vector3d>& tips);
  void ApplyTask(const TaskInput& task, const std::vector<Eigen::Vector3d>& tips);
  void UpdateGravity(const SensedInput& in);
  void UpdateObjectEstimate(const SensedInput& in);
  void UpdateContacts(const SensedInput& in);
  // A finger that touches with a link (not its tip): joint torque its tip force does not
  // explain (contact_sensing.h); an event when it begins.
  void DetectLinkContacts(const SensedInput& in, const std::vector<Eigen::Vector3d>& tips);
  // What the tips' forces, with the friction the joints feel, tell of the object: its friction
  // (each explorer sliding on its tip alone is a probe: friction_observer.h) and its weight
  // (weight_observer.h).
  void ObserveObject(const SensedInput& in, const std::vector<Eigen::Vector3d>& tips);
  Eigen::Isometry3d AdvanceReference();
  GripPlan PlanGrip(const SensedInput& in, const std::vector<Eigen::Vector3d>& tips, bool moving);
  void AdaptGrip(const SensedInput& in, const std::vector<Eigen::Vector3d>& tips,
                 const std::vector<bool>& in_grip, int grip_contacts);
  // SINKING when the grip fingers' tips sink together along gravity while a finger explores
  // (sink_detector.h).
  void DetectSink(const std::vector<Eigen::Vector3d>& tips, const std::vector<bool>& in_grip);
  void StepPosition(int f, const Eigen::Vector3d& tip);
  double StepComposite(int f, const SensedTip& sensed, const Eigen::Vector3d& tip,
                       const GripPlan& grip, const ObjectMotionStep& object);
  double StepHybrid(int f, const SensedTip& sensed, const Eigen::Vector3d& tip,
                    const Eigen::Vector3d& centre);
  void EmitGraspEvents(double time_s, int grip_contacts);
  void EmitMotionEvents(bool moving);

  Eigen::Vector3d ClampAnchorOffset(const Eigen::Vector3d& offset, double sink_m) const;
  double ForceTerm(FingerState* s, const ForceGains& gains, double desired, double measured);
  // The force a finger should get now: its role's force, reached gradually after a role change
  // so that the others' plan changes smoothly (a grip finger that lets go is a step load).
  double Ramp(const FingerState& s, double role_force) const;
  // One tick of the load estimate (load_estimator.h); the net force the grip should carry.
  Eigen::Vector3d LearnLoad(const SensedInput& in, const std::vector<Eigen::Vector3d>& tips,
                            const std::vector<bool>& in_grip, int grip_contacts);
  void Emit(EventType type, int finger, double value, std::string text);

  const HandKinematics& kin_;
  ControllerParams params_;
  double dt_;
  SensedClock clock_{0.1};  // a step of the sensed clock over 0.1 s is a gap
  double now_ = 0.0;        // clock_.now() at this step
  std::vector<FingerState> fingers_;
  std::vector<Eigen::Vector3d> tip_axes_;  // each fingertip's axis this tick (palm frame)
  GripAdapter grip_;
  LoadEstimator load_;
  FrictionObserver friction_;
  WeightObserver weight_;
  SinkDetector sink_;
  double held_n_ = 0.0;  // what the pushes hold up against gravity (normals_aim), low-passed
  Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();  // its direction in the palm frame (IMU)
  bool has_gravity_ = false;
  int last_grip_set_ = 0;  // bit f: finger f grips (the load's seat restarts when it changes)
  ControllerOutput out_;
  int32_t task_id_ = -1;
  bool has_estimate_ = false;
  bool has_contacts_ = false;  // the contact state was taken from a first reading
  Eigen::Isometry3d estimate_ = Eigen::Isometry3d::Identity();
  bool has_reference_ = false;
  Eigen::Isometry3d reference_ = Eigen::Isometry3d::Identity();
  bool has_goal_ = false;
  Eigen::Isometry3d goal_ = Eigen::Isometry3d::Identity();
  double max_linear_ = 0.0, max_angular_ = 0.0;
  bool motion_done_sent_ = false;
  bool tracking_error_sent_ = false;
  bool stable_sent_ = false;
  bool grasp_lost_sent_ = false;
  double stable_since_ = -1.0;
};

}  // namespace dmpl
