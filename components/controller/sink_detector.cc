#include "components/controller/sink_detector.h"

namespace dmpl {

bool SinkDetector::Update(double time_s,
                          const std::vector<std::optional<Eigen::Vector3d>>& grip_tips,
                          const Eigen::Vector3d& gravity, bool exploring) {
  unsigned grip_set = 0;
  double along = 0.0;
  int n = 0;
  const bool sensed = gravity.norm() > 1e-6;
  const Eigen::Vector3d down = sensed ? Eigen::Vector3d(gravity.normalized())
                                      : Eigen::Vector3d::Zero();
  for (size_t f = 0; f < grip_tips.size(); ++f) {
    if (!grip_tips[f]) continue;
    grip_set |= 1u << f;
    along += grip_tips[f]->dot(down);
    ++n;
  }
  speed_ = 0.0;
  if (!params_.enabled || !exploring || !sensed || n < 2 || grip_set != grip_set_) {
    grip_set_ = grip_set;
    along_.clear();
    return false;
  }
  along_.emplace_back(time_s, along / n);
  while (along_.size() > 1 && time_s - along_[1].first >= params_.window_s) along_.pop_front();
  const double span = time_s - along_.front().first;
  if (span < 0.5 * params_.window_s) return false;
  speed_ = (along_.back().second - along_.front().second) / span;
  if (speed_ <= params_.speed_m_per_s || time_s - last_sink_ < params_.refractory_s) return false;
  last_sink_ = time_s;
  return true;
}

}  // namespace dmpl
