#pragma once
// Goal orientations for a gait: the rotation that takes the sensed orientation to a goal the
// shortest way, the goals a config names (task.axis, task.goals), random goals drawn from the
// run's seed, and the sequence of goals a gait works through (reached when the sensed orientation
// stays within a tolerance for a while; a goal not reached in time ends the sequence). Pure.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <yaml-cpp/yaml.h>

namespace dmpl {

// task.axis: x, y or z, or a vector [ax, ay, az] in the palm frame (normalized on reading).
struct AxisParam {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  std::string name = "x";  // x, y or z as written; empty for a vector

  static AxisParam FromYaml(const YAML::Node& node);
  YAML::Node ToYaml() const;
};

// One goal orientation in the palm frame: a quaternion [w, x, y, z] (normalized on reading) or
// {rpy: [roll, pitch, yaw]} in rad about the fixed x, y, z axes (R = Rz(yaw) Ry(pitch) Rx(roll)).
struct OrientationParam {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();

  static OrientationParam FromYaml(const YAML::Node& node);
  YAML::Node ToYaml() const;  // always [w, x, y, z]
};

// The rotation `to` = R(axis, angle) * `from` with the least angle (in [0, pi]); axis in the palm
// frame. At angle 0 the axis is x; at pi (two shortest ways) it is the one the quaternion gives.
struct AxisAngle {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double angle = 0.0;
};
AxisAngle RotationToGoal(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to);

// `count` orientations uniform over SO(3), drawn from `seed` alone, each at least
// `min_separation_rad` (at most pi) from the one before it; the first from `start`.
std::vector<Eigen::Quaterniond> RandomGoals(uint64_t seed, int count, double min_separation_rad,
                                            const Eigen::Quaterniond& start);

// Works through goals one after another.
class GoalSequence {
 public:
  enum class Event { kNone, kReached, kTimedOut };

  GoalSequence() = default;
  // `timeout_s` <= 0: no timeout.
  GoalSequence(std::vector<Eigen::Quaterniond> goals, double tolerance_rad, double hold_s,
               double timeout_s);

  // The current goal starts counting its time now.
  void Start(double now_s);
  // One tick with the sensed orientation. kReached: the current goal has been within the
  // tolerance for hold_s (the next one is now current, or the sequence is complete); kTimedOut:
  // the current goal was not reached within its timeout (the sequence stops there).
  Event Update(double now_s, const Eigen::Quaterniond& sensed);

  bool empty() const { return goals_.empty(); }
  bool complete() const { return reached_ == static_cast<int>(goals_.size()); }
  bool timed_out() const { return timed_out_; }
  int size() const { return static_cast<int>(goals_.size()); }
  int reached() const { return reached_; }  // consecutive, from the first
  const Eigen::Quaterniond& current() const;  // the last goal once complete
  double error_rad() const { return error_; }  // to the current goal at the last update
  const std::vector<double>& times_s() const { return times_; }  // per reached goal

 private:
  std::vector<Eigen::Quaterniond> goals_;
  double tolerance_ = 0.4;
  double hold_ = 0.5;
  double timeout_ = 0.0;
  int reached_ = 0;
  bool timed_out_ = false;
  double started_ = 0.0;
  double within_since_ = -1.0;
  double error_ = 0.0;
  std::vector<double> times_;
};

}  // namespace dmpl
