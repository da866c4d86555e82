#include "components/controller/weight_observer.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

WeightObserver::WeightObserver(const WeightObserverParams& params)
    : params_(params), samples_(params.window) {}

void WeightObserver::Update(double time_s, const Eigen::Vector3d& tips_force,
                            const Eigen::Vector3d& down, bool readable) {
  if (!readable || !tips_force.allFinite() || !down.allFinite() || down.isZero()) {
    filtering_ = false;
    return;
  }
  if (!filtering_) {
    // The filter starts afresh; its first time constant is not a reading yet.
    filtering_ = true;
    filtered_ = tips_force;
    last_time_ = time_s;
    next_sample_ = time_s + params_.time_constant_s;
    return;
  }
  const double dt = std::max(0.0, time_s - last_time_);
  last_time_ = time_s;
  const double a = params_.time_constant_s > 0 ? dt / (params_.time_constant_s + dt) : 1.0;
  filtered_ += a * (tips_force - filtered_);
  if (time_s < next_sample_) return;
  next_sample_ = time_s + params_.sample_every_s;
  samples_.Add(filtered_.dot(down.normalized()));
  if (samples() >= params_.min_samples) weight_ = std::max(0.0, samples_.Median());
}

}  // namespace dmpl
