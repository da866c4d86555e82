#include "components/controller/load_estimator.h"

#include <algorithm>
#include <cmath>

#include "components/runtime/check.h"

namespace dmpl {

LoadEstimator::LoadEstimator(const LoadParams& params) : params_(params) {}

Eigen::Vector3d LoadEstimator::Update(double dt_s, const Eigen::Vector3d& position,
                                      const Eigen::Vector3d& gravity, bool holding) {
  if (!params_.enabled) return Eigen::Vector3d::Zero();
  DMPL_DEMAND(gravity.norm() > 0);
  up_ = -gravity.normalized();
  if (!holding) {
    reference_.reset();  // the object may be anywhere when the grip holds it again
    return load();
  }
  if (!reference_) reference_ = position;
  const double sink = up_.dot(*reference_ - position);
  const double beyond = std::copysign(std::max(0.0, std::abs(sink) - params_.deadband_m), sink);
  load_ = std::clamp(load_ + params_.integral_gain * dt_s * beyond, 0.0, params_.max_load_n);
  if (params_.reference_follow_s > 0) {
    *reference_ += (position - *reference_) * (dt_s / (params_.reference_follow_s + dt_s));
  }
  const double net = std::clamp(load_ + params_.proportional_gain * beyond, 0.0,
                                params_.max_net_force_n);
  return net * up_;
}

}  // namespace dmpl
