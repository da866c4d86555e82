#include "components/controller/friction_observer.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

FrictionObserver::FrictionObserver(const FrictionObserverParams& params) : params_(params) {
  ratios_.reserve(static_cast<size_t>(params_.window));
}

void FrictionObserver::AddSlide(double push_n, double tangential_n) {
  if (!std::isfinite(push_n) || !std::isfinite(tangential_n)) return;
  if (push_n < params_.min_push_n || push_n <= 0.0) return;
  const double ratio = std::abs(tangential_n) / push_n;
  if (static_cast<int>(ratios_.size()) < params_.window) {
    ratios_.push_back(ratio);
  } else {
    ratios_[static_cast<size_t>(count_ % params_.window)] = ratio;
  }
  ++count_;
  if (++since_median_ >= params_.update_every && samples() >= params_.min_samples) TakeMedian();
}

void FrictionObserver::TakeMedian() {
  since_median_ = 0;
  std::vector<double> sorted = ratios_;
  const auto mid = sorted.begin() + static_cast<long>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  friction_ = *mid;
}

}  // namespace dmpl
