#pragma once
// The supervisor's vocabulary: the grasp chart's states and events, what it reads of the
// controller, and what it sends.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/controller/controller_types.h"
#include "components/runtime/sim_request.h"

namespace dmpl {

enum class GraspState {
  ObjectHeld, Approaching, Gripping, Releasing, Settling, Tasks, Recovering, Holding, Done, Failed
};
enum class GraspEvent {
  Start, AllTouching, GraspStable, ReleaseDue, Settled, TaskDone, TaskFailed, ContactLost, LinkRest,
  Slip, Recovered, ProcessLost, ProcessBack, GraspLost, Timeout
};
const char* ToString(GraspState s);
const char* ToString(GraspEvent e);
// `value` with `digits` after the point: a number in the supervisor's notes.
std::string Fixed(double value, int digits = 2);
// What a grasp event carries: why (for the log, the status and the action that handles it) and
// the finger it is about.
struct GraspEventData {
  std::string reason;
  int finger = -1;  // -1: not about one finger
};

struct FingerView {
  bool in_contact = false;
  double force = 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();      // the tip sphere's centre (palm frame)
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();  // the sensed contact point, in contact
  Eigen::Vector3d tip_axis = Eigen::Vector3d::UnitZ();  // the distal link's direction (unit)
  double desired_force = 0.0;  // what the controller plans for it (N)
  // Whether `contact` is a point sensed now: in contact, a reading of at least 0.05 N, on the
  // tip sphere (2-30 mm from its centre). The controller holds `in_contact` through a short
  // loss (its debounce) while the sensor already reports no point (zeros): such a finger still
  // grips, but its point is no contact.
  bool SensesPoint() const;
  // The angle between the tip's axis and the normal into the object at its contact (0: it
  // touches with its front; near 90 deg and beyond, with the side next to its distal link,
  // which touches next). 0 without a sensed point (SensesPoint).
  double ContactAngle() const;
};

// What the supervisor reads from one controller status.
struct ControllerView {
  int64_t seq = 0;
  double time_s = 0.0;
  std::vector<FingerView> fingers;
  Eigen::Isometry3d object = Eigen::Isometry3d::Identity();  // the controller's estimate
  std::vector<ControllerEvent> events;
  bool motion_done = false;
  bool grasp_stable = false;
  double tracking_error_rad = 0.0;  // the object estimate against the controller's reference
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // unit, palm frame; zero until sensed
  double observed_friction = 0.0;  // the explorers' slides (friction_observer.h); 0: not yet
  double observed_weight_n = 0.0;  // what the tips carry (weight_observer.h); 0: not yet
};

struct SupervisorOutput {
  TaskInput task;                       // the controller's task for the next tick
  SimRequest sim = SimRequest::kNone;   // a simulator control to send with this tick's seq
  bool changed = false;                 // state, action or task changed this tick
};

}  // namespace dmpl
