#pragma once
// The object's commanded pose (palm frame) and the rotation commanded so far, about the task's
// axis: every task turns the goal through here, so the account of what was commanded, what
// happened and what is left stays in one place.
#include <Eigen/Geometry>

#include "supervisor/blackboard.h"

namespace dmpl {

class ObjectGoal {
 public:
  ObjectGoal(Blackboard* board, const Eigen::Vector3d& task_axis);

  bool has_goal() const { return has_goal_; }
  const Eigen::Isometry3d& pose() const { return goal_; }
  double commanded() const { return commanded_; }  // rad about the task's axis
  double to_command() const { return to_command_; }
  double remaining() const { return to_command_ - commanded_; }
  void CommandInAll(double more) { to_command_ = commanded_ + more; }  // of the task under way

  // The first task: the goal and the start are where the object is.
  void Begin(const Eigen::Isometry3d& object);
  // To `orientation` (the commanded rotation grows by `angle`) at `speed` rad/s.
  void Aim(const Eigen::Matrix3d& orientation, double angle, double speed);
  // By `angle` about `axis` from the goal (the commanded rotation grows by its part about the
  // task's axis).
  void Turn(const Eigen::Vector3d& axis, double angle, double speed);
  // Back to the orientation the first task began with.
  void TurnBackToStart(double speed);
  // The goal where the sensed object is: the rotation that did not happen is taken back from
  // the account.
  void HoldWhereItIs();
  // As HoldWhereItIs, at the position the goal had (an object that drifted away from a finger
  // is brought back into its reach).
  void HoldTurnedWhereItIs();
  void Send();  // the goal, as it is, goes out with the task

 private:
  Blackboard* board_;
  Eigen::Vector3d task_axis_;
  bool has_goal_ = false;
  Eigen::Isometry3d goal_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d start_ = Eigen::Isometry3d::Identity();
  double commanded_ = 0.0;
  double to_command_ = 0.0;
};

}  // namespace dmpl
