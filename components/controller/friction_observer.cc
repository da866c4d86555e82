#include "components/controller/friction_observer.h"

#include <cmath>

namespace dmpl {

FrictionObserver::FrictionObserver(const FrictionObserverParams& params)
    : params_(params), ratios_(params.window) {}

void FrictionObserver::AddSlide(double push_n, double tangential_n) {
  if (!std::isfinite(push_n) || !std::isfinite(tangential_n)) return;
  if (push_n < params_.min_push_n || push_n <= 0.0) return;
  ratios_.Add(std::abs(tangential_n) / push_n);
  if (++since_median_ < params_.update_every || samples() < params_.min_samples) return;
  since_median_ = 0;
  friction_ = ratios_.Median();
}

}  // namespace dmpl
