#pragma once
// The object sinking out of the grip while a finger explores. With the explorer eased, three
// fingers hold the object; when their squeeze cannot carry it (a pair standing above the
// object's equator pushes it along gravity, and a slick or heavy object outgrows the friction),
// the object sinks, and the fingers give with it: their tips, by forward kinematics of the
// sensed joints, move along gravity together before the object's estimate (a camera's, with
// half a centimetre of noise) can say so. Their mean speed along gravity over a short window
// above a threshold is a sink; the explorer can then take hold again before the object is gone.
// Pure: no LCM, no object model.
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "components/runtime/params.h"

namespace dmpl {

// controller.sink_detector
struct SinkDetectorParams {
  bool enabled = false;
  double speed_m_per_s = 0.05;  // the grip tips' mean speed along gravity that is a sink
  double window_s = 0.02;       // measured over this
  double refractory_s = 0.2;    // a sink keeps counting as one this long

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(enabled));
    a->Visit(DMPL_NVP(speed_m_per_s), Above(0));
    a->Visit(DMPL_NVP(window_s), Above(0));
    a->Visit(DMPL_NVP(refractory_s), AtLeast(0));
  }
};

class SinkDetector {
 public:
  explicit SinkDetector(const SinkDetectorParams& params) : params_(params) {}

  // One tick at `time_s`: the grip fingers' tip centres (palm frame; nothing for a finger not
  // gripping), gravity's direction (palm frame, any length; zero: not sensed) and whether a
  // finger explores. True on the tick a sink begins. The window restarts whenever the grip
  // changes (who grips), nothing explores, fewer than two tips grip or gravity is not sensed.
  bool Update(double time_s, const std::vector<std::optional<Eigen::Vector3d>>& grip_tips,
              const Eigen::Vector3d& gravity, bool exploring);
  // m/s: the grip tips' mean speed along gravity over the last window (0: none measured).
  double speed() const { return speed_; }

 private:
  SinkDetectorParams params_;
  unsigned grip_set_ = 0;
  std::deque<std::pair<double, double>> along_;  // (time, mean tip position along gravity)
  double speed_ = 0.0;
  double last_sink_ = -1e9;
};

}  // namespace dmpl
