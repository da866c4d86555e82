#include "components/controller/position_planner.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

Eigen::Isometry3d ObjectMotion(const Eigen::Isometry3d& current, const Eigen::Isometry3d& target) {
  return current.inverse() * target;
}

Eigen::Vector3d MoveWithObject(const Eigen::Isometry3d& current, const Eigen::Isometry3d& motion,
                               const Eigen::Vector3d& p) {
  return current * (motion * (current.inverse() * p));
}

double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

Eigen::Isometry3d StepToward(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to,
                             double max_linear, double max_angular) {
  const Eigen::Vector3d dp = to.translation() - from.translation();
  const double distance = dp.norm();
  const double angle = AngleBetween(from.linear(), to.linear());
  // The fraction of the way both limits allow, so translation and rotation end together.
  double s = 1.0;
  if (distance > max_linear) s = std::min(s, max_linear / distance);
  if (angle > max_angular) s = std::min(s, max_angular / angle);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translation() = from.translation() + s * dp;
  const Eigen::Quaterniond qa(from.linear()), qb(to.linear());
  out.linear() = qa.slerp(s, qb).normalized().toRotationMatrix();
  return out;
}

}  // namespace dmpl
