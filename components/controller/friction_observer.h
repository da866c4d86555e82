#pragma once
// The friction an explorer's slide shows. An explorer slides over the object pressing lightly
// (the paper's 0.1 N): its contact slips all along, so the friction it drags is the contact's
// full friction times its push. The tip's sensor reads the push; the friction only the joints
// feel (TipTangentialForce). The median ratio of the two over the last slides is what the hand
// has observed of the object's friction. It reads low: part of each slide sticks (Bullet, seed 1
// of the random goals: 0.32 / 0.49 / 0.77 / 1.18 at a true 0.4 / 0.6 / 1.0 / 1.5), so a plan
// that relies on it relies on less than the object gives. A grip, which never leans on its
// contacts' friction beyond about 0.4 of its push whatever the object, tells nothing of it.
// Pure: no LCM, no object model.
#include "components/controller/rolling_median.h"
#include "components/runtime/params.h"

namespace dmpl {

// controller.friction_observer
struct FrictionObserverParams {
  double min_push_n = 0.05;  // a push below this is the sensor's noise: its ratio means nothing
  int window = 3000;         // samples kept (one per explorer tick: about five explores)
  int min_samples = 500;     // before this many the friction is not observed yet
  int update_every = 100;    // the median is taken again after this many new samples

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(min_push_n), AtLeast(0));
    a->Visit(DMPL_NVP(window), InRange(1, 1000000));
    a->Visit(DMPL_NVP(min_samples), InRange(1, 1000000));
    a->Visit(DMPL_NVP(update_every), InRange(1, 1000000));
  }
};

class FrictionObserver {
 public:
  explicit FrictionObserver(const FrictionObserverParams& params);

  // One sliding explorer's tick: its sensed push and the tangential force its joints feel (N).
  void AddSlide(double push_n, double tangential_n);
  // The observed friction coefficient; 0 until min_samples slides have been seen.
  double friction() const { return friction_; }
  int samples() const { return ratios_.size(); }  // kept now

 private:
  FrictionObserverParams params_;
  RollingMedian ratios_;
  int since_median_ = 0;
  double friction_ = 0.0;
};

}  // namespace dmpl
