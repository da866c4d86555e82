#pragma once
// The structural task description of the paper's Fig. 6, loaded from YAML (configs/tasks/):
//  - FIstate: the state of a finger — does it touch the object, which role does it play;
//  - PTask:   a primitive task of one finger — primitive, entry and exit states, transition
//             condition, parameters;
//  - CTask:   a complex task — a PTask sequence per finger plus the desired object motion and its
//             interpolation, and the condition that ends it.
// A task file is the grasp (approach points, Fig. 5) and the list of CTasks to run after it; a
// `gait` CTask hands over to the regrasp statechart (Fig. 4). A new manipulation task is a new
// YAML file, not new code.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/controller/controller_types.h"
#include "components/runtime/params.h"

namespace dmpl {

enum class ContactState { kAny, kTouching, kFree };

struct FIstate {
  ContactState contact = ContactState::kAny;
  std::optional<Role> role;  // nullopt: any role
};

enum class Condition {
  kNone,           // never ends by itself (the CTask's condition ends it)
  kContact,        // the finger touches
  kTargetReached,  // the finger reached its target point
  kGraspStable,    // the controller reports a stable grasp
  kMotionDone,     // the object reached its goal
  kDuration,       // duration_s elapsed
};

struct PTask {
  Primitive primitive = Primitive::kComposite;
  Role role = Role::kGrip;
  FIstate entry, exit;
  Condition until = Condition::kNone;
  double duration_s = 0.0;
  bool has_target = false;
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // palm frame
  double force_n = 0.0;                              // <= 0: the controller's default
};

struct ObjectMotion {
  enum class Reference { kCurrent, kStart };
  Reference reference = Reference::kCurrent;  // rotate from the commanded pose, or back to start
  double angle = 0.0;                         // about `axis`
  bool angle_in_task_units = true;            // angle is a multiple of task.angle (else rad)
  std::string axis = "task";                  // x, y, z, or task (the experiment's task.axis)
  double max_angular_speed = 0.0;             // rad/s; <= 0: task.angular_speed
};

// A local task (per-finger PTask sequences, the paper's Fig. 6) or a gait (the regrasp chart).
enum class TaskType { kLocal, kGait };

struct CTask {
  std::string name;
  TaskType type = TaskType::kLocal;
  std::map<std::string, std::vector<PTask>> fingers;  // finger -> PTask sequence
  std::optional<ObjectMotion> motion;
  Condition done_when = Condition::kMotionDone;
  double duration_s = 0.0;
  double timeout_s = 30.0;
};

// The grasp of Fig. 5 (section `grasp` of a task file).
struct GraspSpec {
  // finger -> contact point to approach (palm frame); none: the fingers already touch
  std::map<std::string, std::array<double, 3>> approach;
  double approach_extension_m = 0.01;  // reached without touching: reach this much further in
  int max_extensions = 3;
  double release_after_stable_s = 0.2;
  double settle_s = 0.5;
  double timeout_s = 10.0;

  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(approach));
    a->Visit(DMPL_NVP(approach_extension_m), InRange(0, 0.1));
    a->Visit(DMPL_NVP(max_extensions), AtLeast(0));
    a->Visit(DMPL_NVP(release_after_stable_s), AtLeast(0));
    a->Visit(DMPL_NVP(settle_s), AtLeast(0));
    a->Visit(DMPL_NVP(timeout_s), Above(0));
  }
};

// The regrasp chart's gait (section `gait` of a task file).
struct GaitSpec {
  std::vector<std::string> order = {"R", "M", "F", "T"};  // the paper's cycle
  double explore_timeout_s = 3.0;
  double rotate_timeout_s = 5.0;
  // A step whose reference has arrived and whose object stopped within this of it counts as done:
  // the next step aims at an absolute orientation, so what is left over is not lost.
  double settle_tolerance_rad = 0.05;
  double settle_time_s = 0.3;
  double grip_timeout_s = 2.0;
  // task.turn=auto: the three grippers turn while the explorer slides when the step's axis is
  // within overlap_max_tilt_rad of overlap_about (palm frame: the axis the fingers stand around),
  // else all four turn after the explorer has gripped again.
  std::array<double, 3> overlap_about = {1.0, 0.0, 0.0};
  double overlap_max_tilt_rad = 0.5;
  // The hand's: how far apart two fingertip centres must stay (their spheres' diameter and a
  // margin); 0: not checked. Around a small object the fingers stand close together: a step
  // turns at most what leaves this between an explorer and the finger it slides back toward
  // (GaitGeometry::StepLimit), and an explorer's point keeps it from that finger.
  double tip_clearance_m = 0.0;

  template <typename A>
  void Serialize(A* a) {
    a->Visit(DMPL_NVP(order));
    a->Visit(DMPL_NVP(explore_timeout_s), Above(0));
    a->Visit(DMPL_NVP(rotate_timeout_s), Above(0));
    a->Visit(DMPL_NVP(grip_timeout_s), Above(0));
    a->Visit(DMPL_NVP(settle_tolerance_rad), Above(0));
    a->Visit(DMPL_NVP(settle_time_s), AtLeast(0));
    a->Visit(DMPL_NVP(overlap_about));
    a->Visit(DMPL_NVP(overlap_max_tilt_rad), InRange(0, 1.5707963267948966));
    a->Visit(DMPL_NVP(tip_clearance_m), InRange(0, 0.1));
  }
};

struct TaskFile {
  std::string name;
  std::string source;
  GraspSpec grasp;
  std::vector<CTask> tasks;
  GaitSpec gait;
};

// Loads and validates a task file against the hand's finger names. Any problem is a ConfigError
// naming the file and the key.
TaskFile LoadTaskFile(const std::string& path, const std::vector<std::string>& fingers);
TaskFile ParseTaskFile(const YAML::Node& root, const std::string& source,
                       const std::vector<std::string>& fingers);

const char* ToString(Condition c);

}  // namespace dmpl
