#pragma once
// The noise injector's core: ground truth in, sensed readings out, as plain values
// (hand_reading.h; no LCM here). Every draw comes from Rng(seed, seq, part) so the same seed gives
// the same readings in any arrival order.
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "sim_process/noise/hand_reading.h"
#include "sim_process/noise/noise_params.h"

namespace dmpl {

class NoiseInjector {
 public:
  NoiseInjector(const NoiseParams& params, int64_t seed);

  // Each returns the sensed reading of tick `seq`, or nullopt when the truth is malformed (NaN,
  // inconsistent sizes, non-unit quaternion): such input is counted and never forwarded.
  std::optional<JointsReading> Sense(int64_t seq, const JointsReading& truth);
  std::optional<ObjectPoseReading> Sense(int64_t seq, const ObjectPoseReading& truth);
  std::optional<std::vector<TipReading>> Sense(int64_t seq, const std::vector<TipReading>& truth);
  // The palm IMU's gravity (m/s^2, palm frame): its direction turned by a small random rotation.
  std::optional<std::array<double, 3>> SenseGravity(int64_t seq, const std::array<double, 3>& truth);
  // A whole tick: each part as above (the same draws), or nullopt when any part is malformed.
  std::optional<HandReading> Sense(const HandReading& truth);

  // Input refused before it reached the injector (a message whose parts disagree on the tick):
  // counted with the rest.
  void Reject(const std::string& why);
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

  NoiseParams params_;
  int64_t seed_;
  Channel<JointsReading> joints_;
  Channel<ObjectPoseReading> object_;
  Channel<std::vector<TipReading>> tactile_;
  int64_t rejected_ = 0;
  int64_t dropped_ = 0;
  std::string last_rejection_;
};

// Whether a reading is one a sensor can give (finite, consistent sizes, a unit quaternion); why
// not, when it is not.
bool IsValid(const JointsReading& r, std::string* why);
bool IsValid(const ObjectPoseReading& r, std::string* why);
bool IsValid(const std::vector<TipReading>& r, std::string* why);

}  // namespace dmpl
