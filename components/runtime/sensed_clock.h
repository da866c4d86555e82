#pragma once
// A clock that runs on the sensed time and stops over the gaps in it. In real time a process of
// the sensing path that restarts leaves a gap: the hand held its last command and nobody saw it.
// What is timed on this clock (timeouts, ramps, how long something has held) does not count
// such time. In lockstep the sensed clock has no gaps and this is the sensed time itself.
namespace dmpl {

class SensedClock {
 public:
  struct Advanced {
    double step_s = 0.0;  // since the last reading (0: the first, after a gap, or not newer)
    double gap_s = 0.0;   // the gap before this reading (0: none)
  };

  // `gap_s`: a longer step between two readings is a gap.
  explicit SensedClock(double gap_s) : gap_s_(gap_s) {}

  Advanced Advance(double sensed_s) {
    Advanced a;
    if (last_s_ >= 0 && sensed_s > last_s_) {
      const double step = sensed_s - last_s_;
      (step > gap_s_ ? a.gap_s : a.step_s) = step;
      unseen_s_ += a.gap_s;
    }
    last_s_ = sensed_s;
    return a;
  }
  double now() const { return last_s_ < 0 ? 0.0 : last_s_ - unseen_s_; }

 private:
  double gap_s_;
  double last_s_ = -1.0;
  double unseen_s_ = 0.0;
};

}  // namespace dmpl
