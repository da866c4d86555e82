#include "sim_process/sim/palm_motion.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

Eigen::Matrix3d RotationFromRpy(const std::array<double, 3>& rpy) {
  return (Eigen::AngleAxisd(rpy[2], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy[0], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d PoseFromXyzRpy(const std::array<double, 3>& xyz, const std::array<double, 3>& rpy) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = RotationFromRpy(rpy);
  t.translation() = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
  return t;
}

PalmMotion::PalmMotion(const PalmMotionParams& params, const Eigen::Matrix3d& initial,
                       const std::string& source)
    : params_(params), initial_(initial) {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'sim.palm_motion." + key + "': " +
                      what);
  };
  CheckBounds(params_, source, "sim.palm_motion");
  turning_ = params.rate_rad_s != 0.0;
  if (turning_) {
    if (!std::isfinite(params.rate_rad_s)) fail("rate_rad_s", "must be finite");
    const Eigen::Vector3d axis(params.axis[0], params.axis[1], params.axis[2]);
    if (!(axis.norm() > 1e-9) || !axis.allFinite()) fail("axis", "must be a non-zero vector");
    axis_ = axis.normalized();
    if (!params.trajectory.empty()) {
      fail("trajectory", "give a turn (rate_rad_s) or a trajectory, not both");
    }
  }
  for (size_t i = 0; i < params.trajectory.size(); ++i) {
    const PalmWaypoint& w = params.trajectory[i];
    const std::string key = "trajectory[" + std::to_string(i) + "]";
    if (!std::isfinite(w.t) || (i > 0 && !(w.t > params.trajectory[i - 1].t))) {
      fail(key + ".t", "times must be finite and increase");
    }
    if (!std::all_of(w.rpy.begin(), w.rpy.end(), [](double x) { return std::isfinite(x); })) {
      fail(key + ".rpy", "must be finite");
    }
    trajectory_.emplace_back(w.t, Eigen::Quaterniond(RotationFromRpy(w.rpy)));
  }
}

Eigen::Matrix3d PalmMotion::Orientation(double t_s) const {
  if (turning_) {
    double angle = params_.rate_rad_s * std::max(0.0, t_s - params_.start_s);
    if (params_.angle_rad > 0) angle = std::clamp(angle, -params_.angle_rad, params_.angle_rad);
    return initial_ * Eigen::AngleAxisd(angle, axis_).toRotationMatrix();
  }
  if (trajectory_.empty()) return initial_;
  if (t_s <= trajectory_.front().first) return trajectory_.front().second.toRotationMatrix();
  if (t_s >= trajectory_.back().first) return trajectory_.back().second.toRotationMatrix();
  const auto next = std::upper_bound(
      trajectory_.begin(), trajectory_.end(), t_s,
      [](double t, const std::pair<double, Eigen::Quaterniond>& w) { return t < w.first; });
  const auto prev = next - 1;
  const double a = (t_s - prev->first) / (next->first - prev->first);
  return prev->second.slerp(a, next->second).toRotationMatrix();
}

Eigen::Vector3d PalmMotion::GravityInPalm(double t_s, const Eigen::Vector3d& gravity_world) const {
  return Orientation(t_s).transpose() * gravity_world;
}

}  // namespace dmpl
