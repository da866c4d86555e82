#pragma once
// The noise injector's core: ground truth in, sensed readings out. No LCM transport here; the
// messages are plain structs. Every draw comes from Rng(seed, seq, channel) so the same seed
// gives the same readings in any arrival order.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/joint_state_t.hpp"
#include "dmpl/object_pose_t.hpp"
#include "dmpl/tactile_t.hpp"
#include "sim_process/noise/noise_params.h"

namespace dmpl {

class NoiseInjector {
 public:
  NoiseInjector(const NoiseParams& params, int64_t seed);

  // Each returns the sensed reading for the truth's seq, or nullopt when the truth is malformed
  // (NaN, inconsistent sizes, non-unit quaternion): such input is counted and never forwarded.
  std::optional<joint_state_t> Sense(const joint_state_t& truth);
  std::optional<object_pose_t> Sense(const object_pose_t& truth);
  std::optional<tactile_t> Sense(const tactile_t& truth);
  // A whole tick: each part as above (the same draws), or nullopt when any part is malformed or
  // the parts disagree on the tick.
  std::optional<hand_sensors_t> Sense(const hand_sensors_t& truth);

  int64_t rejected() const { return rejected_; }
  int64_t dropped() const { return dropped_; }
  const std::string& last_rejection() const { return last_rejection_; }

 private:
  template <typename Msg>
  struct Channel {
    std::deque<Msg> history;       // truth, newest last, for the delay
    std::optional<Msg> last_sent;  // for dropouts
  };
  template <typename Msg>
  const Msg& Delayed(Channel<Msg>* channel, const Msg& truth);
  void Reject(const std::string& why);

  NoiseParams params_;
  int64_t seed_;
  Channel<joint_state_t> joints_;
  Channel<object_pose_t> object_;
  Channel<tactile_t> tactile_;
  int64_t rejected_ = 0;
  int64_t dropped_ = 0;
  std::string last_rejection_;
};

// Validity checks shared with other consumers of these messages.
bool IsFinite(const joint_state_t& m, std::string* why);
bool IsFinite(const object_pose_t& m, std::string* why);
bool IsFinite(const tactile_t& m, std::string* why);

}  // namespace dmpl
