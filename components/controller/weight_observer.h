#pragma once
// The weight a grasp carries, as the fingertips feel it. At rest the forces the tips take from
// the object add up to its weight: each tip's sensed push along its normal plus the friction its
// joints feel (TipTangentialForce). Over one tick the sum chatters with the contacts (a median
// 0.65 N off a 0.49 N weight); low-passed over 0.1 s it is 0.12 N off, and unbiased (random
// goals, Bullet, seed 1). Its part along the sensed gravity, taken while at least three tips hold
// and no link touches (a link carries load the tips do not feel), and the median of the last of
// those, is what the hand has observed of the object's weight. The object's mass is never read.
// Pure: no LCM, no object model.
#include <Eigen/Core>

#include "components/controller/rolling_median.h"
#include "components/runtime/params.h"

namespace dmpl {

// controller.weight_observer
struct WeightObserverParams {
  double time_constant_s = 0.1;  // low-pass of the tips' summed force
  double sample_every_s = 0.01;  // one sample of it this often...
  int window = 2000;             // ...the last this many kept (20 s)...
  int min_samples = 100;         // ...and a weight observed after this many (1 s of holding)

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(time_constant_s), AtLeast(0));
    a->Visit(DMPL_NVP(sample_every_s), Above(0));
    a->Visit(DMPL_NVP(window), InRange(1, 1000000));
    a->Visit(DMPL_NVP(min_samples), InRange(1, 1000000));
  }
};

class WeightObserver {
 public:
  explicit WeightObserver(const WeightObserverParams& params);

  // One tick at `time_s`: the tips' summed force (palm frame, N; the forces the tips take from
  // the object), gravity's direction (unit, palm frame), and whether the grasp is one to read
  // it from (three tips or more, no link). A tick that is not restarts the low-pass.
  void Update(double time_s, const Eigen::Vector3d& tips_force, const Eigen::Vector3d& down,
              bool readable);
  // N: the observed weight; 0 until min_samples samples have been taken.
  double weight() const { return weight_; }
  int samples() const { return samples_.size(); }

 private:
  WeightObserverParams params_;
  bool filtering_ = false;
  double last_time_ = 0.0;
  double next_sample_ = 0.0;
  Eigen::Vector3d filtered_ = Eigen::Vector3d::Zero();
  RollingMedian samples_;
  double weight_ = 0.0;
};

}  // namespace dmpl
