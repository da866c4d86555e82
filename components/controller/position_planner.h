#pragma once
// The position planner of the paper (§II.A): the object motion M = O^-1 O' (1), and contacts that
// move rigidly with the object, p' = O M O^-1 p (2). The desired motion is split into small steps
// of bounded speed (Fig. 1).
#include <Eigen/Geometry>

namespace dmpl {

// Equation (1): M = O^-1 O'.
Eigen::Isometry3d ObjectMotion(const Eigen::Isometry3d& current, const Eigen::Isometry3d& target);

// Equation (2): p' = O M O^-1 p (all in the palm frame).
Eigen::Vector3d MoveWithObject(const Eigen::Isometry3d& current, const Eigen::Isometry3d& motion,
                               const Eigen::Vector3d& p);

// One step of the reference from `from` toward `to`: translation at most max_linear, rotation at
// most max_angular (slerp), both reaching the goal together.
Eigen::Isometry3d StepToward(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to,
                             double max_linear, double max_angular);

// Rotation angle between two orientations.
double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace dmpl
