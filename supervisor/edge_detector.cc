#include "supervisor/edge_detector.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

std::optional<Edge> EdgeDetector::Add(double time_s, const Eigen::Vector3d& point,
                                      const Eigen::Vector3d& normal) {
  while (!trace_.empty() && trace_.front().time_s < time_s - params_.window_s) trace_.pop_front();
  // Still on the edge found last (within reach of it, the normal turned on): that edge, further.
  if (last_ && (last_->point - point).norm() <= params_.max_travel_m &&
      time_s - last_->time_s <= params_.window_s) {
    const double angle = std::acos(std::clamp(last_->normal_before.dot(normal), -1.0, 1.0));
    const bool turned_on = angle > last_->angle_rad + 1e-9;
    // The next face's trace starts where the roll ends, not on its way round.
    trace_.assign(1, {time_s, point, normal});
    if (!turned_on) return std::nullopt;
    last_->time_s = time_s;
    last_->normal_after = normal;
    last_->angle_rad = angle;
    last_->continues = true;
    return last_;
  }
  std::optional<Edge> edge;
  // The earliest sample still within reach of this point whose normal differs enough: the
  // face before the edge. (Earliest: the whole turn, not its last step.)
  for (const Sample& s : trace_) {
    if ((s.point - point).norm() > params_.max_travel_m) continue;
    const double angle = std::acos(std::clamp(s.normal.dot(normal), -1.0, 1.0));
    if (angle < params_.min_turn_rad) continue;
    edge = Edge{time_s, 0.5 * (s.point + point), s.normal, normal, angle};
    break;
  }
  if (edge) {
    last_ = edge;
    trace_.clear();  // the next face starts the trace
  }
  trace_.push_back({time_s, point, normal});
  return edge;
}

}  // namespace dmpl
