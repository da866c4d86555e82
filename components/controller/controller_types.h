#pragma once
// The controller's vocabulary: what goes into a control step (sensed data, the task per finger)
// and what comes out (targets, events). Header-only, so that the supervisor, which plans tasks
// and reads events, depends on these types and not on the controller.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

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
  std::vector<double> effort;      // the servos' joint torques, N m (empty: not sensed)
  std::vector<SensedTip> tips;     // per finger (kinematics order)
  bool object_valid = false;
  Eigen::Isometry3d object = Eigen::Isometry3d::Identity();
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // m/s^2, palm frame (the palm's IMU)
};

struct FingerTask {
  Role role = Role::kFree;
  Primitive primitive = Primitive::kHold;
  bool has_target = false;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double force_n = 0.0;  // <= 0: the controller's default for the role
  // Touching, its tip's front turned toward the surface (the IK's redundancy, ik.approach_gain):
  // asked by the supervisor of a finger whose links come near the felt surface.
  bool face_surface = false;
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
  kLinkContact = 10,  // a finger touches with a link, not its tip (value: the torque, N m)
  kLinkReleased = 11,  // its links no longer touch (after a kLinkContact)
  kSinking = 12,  // while a finger explores, the grip sinks along gravity (value: m/s)
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
  Eigen::Vector3d tip_axis = Eigen::Vector3d::UnitZ();  // the distal link's direction
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
  // Where the tip's axis should point for the IK (unit, into the object at its contact; zero:
  // no preference).
  Eigen::Vector3d approach = Eigen::Vector3d::Zero();
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
  double observed_friction = 0.0;      // what the explorers' slides showed; 0: not yet
  double observed_weight_n = 0.0;      // what the tips' forces carry along gravity; 0: not yet
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // unit, palm frame; zero until sensed
};

}  // namespace dmpl
