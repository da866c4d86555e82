#include "supervisor/object_goal.h"

namespace dmpl {

ObjectGoal::ObjectGoal(Blackboard* board, const Eigen::Vector3d& task_axis)
    : board_(board), task_axis_(task_axis) {}

void ObjectGoal::Begin(const Eigen::Isometry3d& object) {
  start_ = object;
  goal_ = object;
  has_goal_ = true;
}

void ObjectGoal::Aim(const Eigen::Matrix3d& orientation, double angle, double speed) {
  goal_.linear() = orientation;
  has_goal_ = true;
  commanded_ += angle;
  TaskInput& task = board_->out.task;
  task.has_object_target = true;
  task.object_target = goal_;
  task.max_angular_speed = speed;
  board_->motion_done_event = false;
}

void ObjectGoal::Turn(const Eigen::Vector3d& axis, double angle, double speed) {
  Aim(Eigen::AngleAxisd(angle, axis).toRotationMatrix() * goal_.linear(),
      angle * axis.dot(task_axis_), speed);
}

void ObjectGoal::TurnBackToStart(double speed) {
  const Eigen::AngleAxisd back(start_.linear() * goal_.linear().transpose());
  Turn(back.axis(), back.angle(), speed);
  goal_ = start_;
  board_->out.task.object_target = goal_;
}

void ObjectGoal::HoldWhereItIs() {
  const Eigen::Isometry3d& object = board_->view.object;
  if (has_goal_) {
    const Eigen::AngleAxisd diff(goal_.linear() * object.linear().transpose());
    commanded_ -= diff.angle() * diff.axis().dot(task_axis_);
  }
  goal_ = object;
  has_goal_ = true;
  board_->out.task.has_object_target = true;
  board_->out.task.object_target = goal_;
}

void ObjectGoal::HoldTurnedWhereItIs() {
  const Eigen::Vector3d position = goal_.translation();
  const bool had_goal = has_goal_;
  HoldWhereItIs();
  if (had_goal) {
    goal_.translation() = position;
    board_->out.task.object_target = goal_;
  }
}

void ObjectGoal::Send() {
  board_->out.task.has_object_target = has_goal_;
  board_->out.task.object_target = goal_;
}

}  // namespace dmpl
