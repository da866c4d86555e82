#pragma once
// The median of the last `window` values added: what an observer reads through chatter and
// outliers. A ring; the median is taken on demand (nth_element over a copy: O(window)).
#include <algorithm>
#include <vector>

namespace dmpl {

class RollingMedian {
 public:
  explicit RollingMedian(int window) : window_(std::max(window, 1)) {
    values_.reserve(static_cast<size_t>(window_));
  }

  void Add(double value) {
    if (static_cast<int>(values_.size()) < window_) {
      values_.push_back(value);
    } else {
      values_[static_cast<size_t>(next_)] = value;
    }
    next_ = (next_ + 1) % window_;
  }
  int size() const { return static_cast<int>(values_.size()); }  // kept now, at most window
  // The upper median of the values kept; 0 with none.
  double Median() const {
    if (values_.empty()) return 0.0;
    std::vector<double> sorted = values_;
    const auto mid = sorted.begin() + static_cast<long>(sorted.size() / 2);
    std::nth_element(sorted.begin(), mid, sorted.end());
    return *mid;
  }

 private:
  int window_;
  int next_ = 0;  // the slot the next value goes to
  std::vector<double> values_;
};

}  // namespace dmpl
