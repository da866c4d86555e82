#pragma once
// The load the grip carries, learned from how the object sinks (issue 14). The paper's force
// planner makes the grip forces add up to zero; an object's weight then rides on friction alone
// and a heavy or slick object slides out when a finger leaves to explore. This estimator watches
// a sensed position of the object along gravity (the palm's IMU says where that is): while
// it sinks faster than its reference follows it (a slow follower, so a steady offset teaches
// nothing), the load grows; it never reads the object's mass. The controller adds the load to
// what the grip forces add up to and squeezes for friction to carry it
// (LoadParams::friction_assumed). Off by default: on the unknown-objects benchmark it has not
// yet helped (the object and the fingertips sink together: the fingers give, the contacts
// barely move on the tips; the camera's noise hides a millimetre): README, "Objects it was not
// tuned on".
// Pure: no LCM, no object model.
#include <array>
#include <optional>

#include <Eigen/Core>

#include "components/runtime/params.h"

namespace dmpl {

struct LoadParams {
  bool enabled = false;
  double proportional_gain = 40.0;  // N/m of sink beyond the deadband, at once
  double integral_gain = 800.0;     // N/(m s): how fast the load is learned
  double deadband_m = 0.0005;       // sinks smaller than this teach nothing (sensor noise)
  double reference_follow_s = 0.3;  // the reference follows the object this slowly (0: fixed)
  double max_load_n = 2.5;          // the learned load's bound (~250 g at 1 g)
  double max_net_force_n = 3.0;     // the bound of load + proportional term
  // Friction carries what the normals cannot: each grip finger squeezes at least
  // load / (fingers * friction_assumed).
  double friction_assumed = 0.5;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(enabled));
    a->Visit(DMPL_NVP(proportional_gain), AtLeast(0));
    a->Visit(DMPL_NVP(integral_gain), AtLeast(0));
    a->Visit(DMPL_NVP(deadband_m), AtLeast(0));
    a->Visit(DMPL_NVP(reference_follow_s), AtLeast(0));
    a->Visit(DMPL_NVP(max_load_n), AtLeast(0));
    a->Visit(DMPL_NVP(max_net_force_n), AtLeast(0));
    a->Visit(DMPL_NVP(friction_assumed), AtLeast(0));
  }
};

class LoadEstimator {
 public:
  explicit LoadEstimator(const LoadParams& params);

  // One tick of `dt_s`. `position`: the object's estimated position (palm frame, m).
  // `gravity`: its direction now (palm frame, the palm's IMU; the palm may turn).
  // `holding`: whether the grip holds the object (at least two grip contacts); the load is
  // learned only then and kept otherwise. Returns the net force the grip forces should add up
  // to (N, palm frame, against gravity).
  Eigen::Vector3d Update(double dt_s, const Eigen::Vector3d& position,
                         const Eigen::Vector3d& gravity, bool holding);

  double load_n() const { return load_; }
  Eigen::Vector3d load() const { return load_ * up_; }
  const Eigen::Vector3d& up() const { return up_; }

 private:
  LoadParams params_;
  Eigen::Vector3d up_ = Eigen::Vector3d::UnitX();  // against gravity, unit
  std::optional<Eigen::Vector3d> reference_;
  double load_ = 0.0;  // N, along up_
};

}  // namespace dmpl
