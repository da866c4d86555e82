#pragma once
// The load the grip carries, learned from where the object goes (issue 14). The paper's force
// planner makes the grip forces add up to zero; an object's weight, and any other steady push
// (a finger that left to explore, a slope of friction), then rides on friction alone and the
// object sinks or drifts a little at every regrasp. This estimator integrates the object's
// position error (reference minus estimate, both sensed) into a steady force the grip must
// carry, plus a proportional term that damps it: the grip forces then add up to that force
// instead of zero. It never reads the object's mass: a heavier object sinks further until the
// learned load carries it, a lighter one is not pushed harder than it needs.
// Pure: no LCM, no object model.
#include <array>

#include <Eigen/Core>

#include "components/runtime/params.h"

namespace dmpl {

struct LoadParams {
  bool enabled = false;
  double proportional_gain = 40.0;  // N/m of position error, at once
  double integral_gain = 800.0;     // N/(m s): how fast the load is learned
  double max_load_n = 2.5;          // the learned load's bound (~250 g at 1 g)
  double max_net_force_n = 3.0;     // the bound of load + proportional term
  // The grip forces aim where the contacts' normals meet (the centre of a sphere, the axis of a
  // cylinder) instead of at the contacts' centroid: along the normals they need no friction,
  // and contacts below the object's equator can carry its weight.
  bool aim_at_normals = true;
  int normals_min_contacts = 4;     // ...when this many fingers grip (three alone rarely balance)
  double max_grip_force_n = 3.0;    // per finger: what the servos hold
  // With fewer fingers the forces meet at the contacts' centroid (the paper) and friction carries
  // the load: each grip finger squeezes at least load / (fingers * this).
  double friction_assumed = 0.5;
  // The direction of gravity in the palm frame, from how the hand is mounted (palm up: -x); the
  // load is learned along it only, so that the camera's noise across it teaches nothing. Zero:
  // a load in every direction.
  std::array<double, 3> gravity_direction = {-1.0, 0.0, 0.0};

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(enabled));
    a->Visit(DMPL_NVP(proportional_gain));
    a->Visit(DMPL_NVP(integral_gain));
    a->Visit(DMPL_NVP(max_load_n));
    a->Visit(DMPL_NVP(max_net_force_n));
    a->Visit(DMPL_NVP(aim_at_normals));
    a->Visit(DMPL_NVP(normals_min_contacts));
    a->Visit(DMPL_NVP(max_grip_force_n));
    a->Visit(DMPL_NVP(friction_assumed));
    a->Visit(DMPL_NVP(gravity_direction));
  }
};

class LoadEstimator {
 public:
  explicit LoadEstimator(const LoadParams& params);

  // One tick of `dt_s`. `error`: the object's reference minus its estimate (palm frame, m).
  // `holding`: whether the grip holds the object (at least two grip contacts); the load is
  // learned only then and kept otherwise. Returns the net force the grip forces should add up
  // to (N, palm frame).
  Eigen::Vector3d Update(double dt_s, const Eigen::Vector3d& error, bool holding);

  const Eigen::Vector3d& load() const { return load_; }

 private:
  LoadParams params_;
  Eigen::Vector3d up_ = Eigen::Vector3d::Zero();  // against gravity, unit; zero: every direction
  Eigen::Vector3d load_ = Eigen::Vector3d::Zero();
};

}  // namespace dmpl
