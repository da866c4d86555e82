#include "sim_process/joint_player/joint_trajectory.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

JointTrajectory::JointTrajectory(const HandModel& model, const std::vector<JointWaypoint>& waypoints,
                                 const std::string& source) {
  auto fail = [&](size_t i, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'joint_player.waypoints[" +
                      std::to_string(i) + "]': " + what);
  };
  if (waypoints.empty()) {
    throw ConfigError("config error in " + source + ": joint_player.waypoints is empty");
  }
  std::vector<double> q(model.num_actuated(), std::nan(""));
  for (size_t i = 0; i < waypoints.size(); ++i) {
    const JointWaypoint& w = waypoints[i];
    if (i > 0 && !(w.t > waypoints[i - 1].t)) fail(i, "times must increase");
    for (const auto& [finger, angles] : w.q) {
      const int f = model.FindFinger(finger);
      if (f < 0) fail(i, "no finger '" + finger + "'");
      const auto& joints = model.fingers()[f].joints;
      if (angles.size() != joints.size()) {
        fail(i, "finger '" + finger + "' needs " + std::to_string(joints.size()) + " angles");
      }
      for (size_t k = 0; k < joints.size(); ++k) {
        const JointInfo& joint = model.actuated_joint(joints[k]);
        if (angles[k] < joint.lower || angles[k] > joint.upper) {
          fail(i, "joint '" + joint.name + "' angle " + std::to_string(angles[k]) +
                      " is outside its limits");
        }
        q[joints[k]] = angles[k];
      }
    }
    for (int a = 0; a < model.num_actuated(); ++a) {
      if (std::isnan(q[a])) {
        fail(i, "joint '" + model.actuated_joint(a).name + "' has no angle yet (give every "
                "finger in the first waypoint)");
      }
    }
    times_.push_back(w.t);
    points_.push_back(q);
  }
}

std::vector<double> JointTrajectory::At(double t) const {
  if (t <= times_.front()) return points_.front();
  if (t >= times_.back()) return points_.back();
  const size_t i = std::upper_bound(times_.begin(), times_.end(), t) - times_.begin();
  const double u = (t - times_[i - 1]) / (times_[i] - times_[i - 1]);
  const double s = u * u * (3.0 - 2.0 * u);  // smoothstep
  std::vector<double> q(points_[i].size());
  for (size_t a = 0; a < q.size(); ++a) q[a] = points_[i - 1][a] + s * (points_[i][a] - points_[i - 1][a]);
  return q;
}

}  // namespace dmpl
