#include "components/controller/load_estimator.h"

namespace dmpl {
namespace {

Eigen::Vector3d Clamp(const Eigen::Vector3d& v, double max_norm) {
  const double n = v.norm();
  return n > max_norm ? Eigen::Vector3d(v * (max_norm / n)) : v;
}

}  // namespace

LoadEstimator::LoadEstimator(const LoadParams& params) : params_(params) {
  const Eigen::Vector3d g(params.gravity_direction[0], params.gravity_direction[1],
                          params.gravity_direction[2]);
  if (g.norm() > 0) up_ = -g.normalized();
}

Eigen::Vector3d LoadEstimator::Update(double dt_s, const Eigen::Vector3d& raw_error, bool holding) {
  if (!params_.enabled) return Eigen::Vector3d::Zero();
  if (!holding) return load_;
  const Eigen::Vector3d error = up_.isZero() ? raw_error : Eigen::Vector3d(up_.dot(raw_error) * up_);
  load_ = Clamp(load_ + params_.integral_gain * dt_s * error, params_.max_load_n);
  return Clamp(load_ + params_.proportional_gain * error, params_.max_net_force_n);
}

}  // namespace dmpl
