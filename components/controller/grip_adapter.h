#pragma once
// A grip that adapts to an unknown load and friction, from what the hand senses:
//  - the explorer's share: when a finger leaves the grip to explore, the grip fingers that remain
//    take over its share of the squeeze (the force planner balances only the grip fingers, and
//    the object's weight does not lighten with them);
//  - incipient slip: an object sliding through the grip moves every grip contact the same way
//    over its fingertip (contact point minus tip centre), while turning it or rolling moves the
//    contacts in different directions. The common-mode speed of the contacts over their tips
//    (each contact low-passed, the speed over a window: contact points chatter) above a
//    threshold is a slip; each slip raises the grip by a factor and the
//    raise is kept (the load learned) for the rest of the run, up to a force the servos hold.
// Pure: no LCM, no object model. Off by default (controller.grip_adaptation.enabled); the fast
// gait turns it on together with controller.normals_aim: alone, a harder squeeze aimed at the
// contacts' centroid pops a slick object out of a three-finger grip; along the normals it holds
// (README, "Objects it was not tuned on").
#include <Eigen/Core>
#include <deque>
#include <optional>
#include <vector>

#include "components/runtime/params.h"

namespace dmpl {

struct GripAdaptationParams {
  bool enabled = false;
  double slip_speed_m_per_s = 0.008;   // common-mode speed of the contacts over their tips
  double slip_time_constant_s = 0.01;  // low-pass of each contact's offset (they chatter)...
  double slip_window_s = 0.05;         // ...and the window the speed is measured over
  double raise_factor = 1.3;           // the grip's scale after each slip
  double refractory_s = 0.15;          // a slip keeps counting as one this long
  double max_grip_force_n = 2.5;       // per finger: what the servos hold without saturating
  bool share_explorer_load = true;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(enabled));
    a->Visit(DMPL_NVP(slip_speed_m_per_s), Above(0));
    a->Visit(DMPL_NVP(slip_time_constant_s), AtLeast(0));
    a->Visit(DMPL_NVP(slip_window_s), Above(0));
    a->Visit(DMPL_NVP(raise_factor), InRange(1, 3));
    a->Visit(DMPL_NVP(refractory_s), AtLeast(0));
    a->Visit(DMPL_NVP(max_grip_force_n));
    a->Visit(DMPL_NVP(share_explorer_load));
  }
};

// Detects slip from the grip contacts' offsets on their fingertips.
class SlipDetector {
 public:
  SlipDetector(double threshold_m_per_s, double time_constant_s, double window_s)
      : threshold_(threshold_m_per_s), tau_(time_constant_s), window_(window_s) {}

  // One tick: per finger, the contact point minus the tip centre (palm frame) of a grip finger
  // in contact, or nothing. Returns true while the common-mode speed is above the threshold.
  bool Update(double time_s, const std::vector<std::optional<Eigen::Vector3d>>& offsets);
  // Forgets the last offsets (a finger joined or left the grip: its jump is no slip).
  void Reset();
  double speed() const { return speed_; }

 private:
  using Offsets = std::vector<std::optional<Eigen::Vector3d>>;
  double threshold_, tau_, window_;
  double last_time_ = -1.0;
  Offsets filtered_;                             // per finger, low-passed
  std::deque<std::pair<double, Offsets>> past_;  // the filtered offsets over the window
  double speed_ = 0.0;
};

// The grip force per finger: nominal x learned load scale x explorer share, capped.
class GripAdapter {
 public:
  GripAdapter(const GripAdaptationParams& params, double nominal_n)
      : params_(params),
        nominal_(nominal_n),
        detector_(params.slip_speed_m_per_s, params.slip_time_constant_s, params.slip_window_s) {}

  // One tick. `offsets` as SlipDetector; `grip_fingers`: fingers gripping now; `holding_fingers`:
  // fingers gripping or exploring (those that hold the object between them). Returns true on
  // the tick a new slip is detected (the scale has just been raised). Does nothing when off.
  bool Update(double time_s, const std::vector<std::optional<Eigen::Vector3d>>& offsets,
              int grip_fingers, int holding_fingers);

  double grip_force() const;  // per grip finger, N
  double load_scale() const { return scale_; }
  double slip_speed() const { return detector_.speed(); }
  int slips() const { return slips_; }

 private:
  GripAdaptationParams params_;
  double nominal_;
  SlipDetector detector_;
  double scale_ = 1.0;
  double share_ = 1.0;
  double last_slip_ = -1e9;
  int slips_ = 0;
  int last_grip_ = -1;
};

}  // namespace dmpl
