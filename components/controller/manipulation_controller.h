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
#include "components/controller/force_planner.h"
#include "components/controller/grip_adapter.h"
#include "components/controller/load_estimator.h"
#include "components/kinematics/hand_kinematics.h"

namespace dmpl {

enum class Role : int8_t { kFree = 0, kGrip = 1, kExplore = 2 };
enum class Primitive : int8_t { kHold = 0, kPosition = 1, kComposite = 2, kHybrid = 3 };

struct SensedTip {
  bool in_contact = false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // contact point, palm frame
  double force = 0.0;                                  // normal force magnitude, N
};

struct SensedInput {
  int64_t seq = 0;
  double time_s = 0.0;
  std::vector<double> q;           // hand joint vector
  std::vector<SensedTip> tips;     // per finger (kinematics order)
  bool object_valid = false;
  Eigen::Isometry3d object = Eigen::Isometry3d::Identity();
};

struct FingerTask {
  Role role = Role::kFree;
  Primitive primitive = Primitive::kHold;
  bool has_target = false;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double force_n = 0.0;  // <= 0: the controller's default for the role
};

struct TaskInput {
  int32_t task_id = 0;
  std::string name = "idle";
  bool has_object_target = false;
  Eigen::Isometry3d object_target = Eigen::Isometry3d::Identity();
  double max_linear_speed = 0.0;   // <= 0: default
  double max_angular_speed = 0.0;  // <= 0: default
  std::vector<FingerTask> fingers;  // per finger (kinematics order)
};

enum class EventType : int8_t {
  kContactMade = 1,
  kContactLost = 2,
  kMotionDone = 3,
  kGraspStable = 4,
  kInputRejected = 5,
  kTrackingError = 6,
  kTargetReached = 7,
  kGraspLost = 8,
  kSlip = 9,
};

struct ControllerEvent {
  EventType type;
  int finger = -1;  // -1: not about one finger
  double value = 0.0;
  std::string text;
};

struct FingerOutput {
  Role role = Role::kFree;
  Primitive primitive = Primitive::kHold;
  bool in_contact = false;             // debounced
  double force = 0.0;
  double desired_force = 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
  bool track = false;                  // false: the IK holds this finger
};

struct ControllerOutput {
  int64_t seq = 0;
  int32_t task_id = 0;
  std::vector<FingerOutput> fingers;
  std::vector<ControllerEvent> events;
  bool motion_done = false;
  bool grasp_stable = false;
  double tracking_error_rad = 0.0;     // estimate vs reference
  double tracking_error_m = 0.0;
  Eigen::Isometry3d object_estimate = Eigen::Isometry3d::Identity();
  Eigen::Vector3d contact_centroid = Eigen::Vector3d::Zero();
  double grip_force_n = 0.0;           // planned per grip finger (GripAdapter)
  double load_scale = 1.0;
};

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
  };

  bool Validate(const SensedInput& in, std::string* why) const;
  void ApplyTask(const TaskInput& task, const std::vector<Eigen::Vector3d>& tips);
  void UpdateObjectEstimate(const SensedInput& in);
  void UpdateContacts(const SensedInput& in);
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
  double now_ = 0.0;
  double last_time_ = -1.0;
  std::vector<FingerState> fingers_;
  GripAdapter grip_;
  LoadEstimator load_;
  Eigen::Vector3d gravity_;  // its direction in the palm frame (controller.gravity_direction)
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
