#include "components/controller/grip_adapter.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

bool SlipDetector::Update(double time_s, const Offsets& offsets) {
  const double dt = last_time_ >= 0 ? time_s - last_time_ : 0.0;
  last_time_ = time_s;
  if (filtered_.size() != offsets.size()) {
    filtered_.assign(offsets.size(), std::nullopt);
    past_.clear();
  }
  const double a = tau_ > 0 && dt > 0 ? std::min(1.0, dt / tau_) : 1.0;
  for (size_t f = 0; f < offsets.size(); ++f) {
    if (!offsets[f]) {
      filtered_[f].reset();
    } else if (!filtered_[f]) {
      filtered_[f] = offsets[f];
    } else {
      *filtered_[f] += a * (*offsets[f] - *filtered_[f]);
    }
  }
  past_.emplace_back(time_s, filtered_);
  while (past_.size() > 1 && time_s - past_[1].first >= window_) past_.pop_front();
  // The mean motion, over the window, of the contacts present at both of its ends. Two contacts
  // at least: one contact moving over its tip may as well be rolling.
  const auto& [then, before] = past_.front();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (size_t f = 0; f < filtered_.size(); ++f) {
    if (filtered_[f] && before[f]) {
      sum += *filtered_[f] - *before[f];
      ++n;
    }
  }
  const double span = time_s - then;
  speed_ = n >= 2 && span >= 0.5 * window_ ? sum.norm() / (n * span) : 0.0;
  return speed_ > threshold_;
}

void SlipDetector::Reset() {
  filtered_.assign(filtered_.size(), std::nullopt);
  past_.clear();
  speed_ = 0.0;
}

bool GripAdapter::Update(double time_s, const std::vector<std::optional<Eigen::Vector3d>>& offsets,
                         int grip_fingers, int holding_fingers) {
  if (!params_.enabled) return false;
  share_ = params_.share_explorer_load && grip_fingers >= 2 && holding_fingers > grip_fingers
               ? static_cast<double>(holding_fingers) / grip_fingers
               : 1.0;
  if (grip_fingers != last_grip_) {
    detector_.Reset();  // a finger joined or left: its contact jump is not a slip
    last_grip_ = grip_fingers;
  }
  const bool slipping = detector_.Update(time_s, offsets);
  if (!slipping || time_s - last_slip_ < params_.refractory_s) return false;
  last_slip_ = time_s;
  if (grip_force() >= params_.max_grip_force_n) return false;  // nothing left to raise
  scale_ *= params_.raise_factor;
  ++slips_;
  return true;
}

double GripAdapter::grip_force() const {
  const double f = nominal_ * (params_.enabled ? scale_ * share_ : 1.0);
  return std::min(f, std::max(nominal_, params_.max_grip_force_n));
}

}  // namespace dmpl
