#pragma once
// How the palm turns while a task runs (sim.palm_motion): at a constant angular velocity about
// an axis of the palm, or through a recorded trajectory of palm orientations. The simulator
// keeps the hand where it is and turns gravity the other way: everything it reports is in the
// palm frame, where a turning palm shows as gravity turning. What that leaves out is the
// inertial force of the turn itself (omega^2 r: 0.002 m/s^2 for an object 7 cm from the palm
// at 0.2 rad/s, 0.02 % of gravity), which this models as zero.
// Pure: no Bullet, no LCM.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/runtime/params.h"

namespace dmpl {

struct PalmWaypoint {
  double t = 0.0;                      // s
  std::array<double, 3> rpy = {0, 0, 0};  // the palm's orientation in the world, as sim.palm_rpy
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(t));
    a->Visit(DMPL_NVP(rpy));
  }
};

// Section `sim.palm_motion`. Either a turn (rate_rad_s about axis from start_s, for angle_rad)
// or a trajectory (orientations at increasing times, slerped between, held after the last);
// neither: the palm stands still.
struct PalmMotionParams {
  std::array<double, 3> axis = {0, 0, 1};  // palm frame
  double rate_rad_s = 0.0;                 // 0: no turn
  double start_s = 0.0;
  double angle_rad = 0.0;                  // the turn stops after this much (0: never)
  std::vector<PalmWaypoint> trajectory;
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(axis));
    a->Visit(DMPL_NVP(rate_rad_s));
    a->Visit(DMPL_NVP(start_s), AtLeast(0));
    a->Visit(DMPL_NVP(angle_rad), AtLeast(0));
    a->Visit(DMPL_NVP(trajectory));
  }
};

// The palm's orientation in the world, as a rotation matrix built like sim.palm_rpy's.
Eigen::Matrix3d RotationFromRpy(const std::array<double, 3>& rpy);
// A pose from a position and roll-pitch-yaw, as the configs give them.
Eigen::Isometry3d PoseFromXyzRpy(const std::array<double, 3>& xyz, const std::array<double, 3>& rpy);

class PalmMotion {
 public:
  // `initial`: the palm's orientation in the world before it moves (sim.palm_rpy). Throws
  // ConfigError naming `source` and the key on a zero axis, a turn and a trajectory at once, or
  // times that do not increase.
  PalmMotion(const PalmMotionParams& params, const Eigen::Matrix3d& initial,
             const std::string& source);

  bool moves() const { return turning_ || !trajectory_.empty(); }
  // The palm's orientation in the world at time t.
  Eigen::Matrix3d Orientation(double t_s) const;
  // Gravity (world frame `gravity_world`) as the palm sees it at time t.
  Eigen::Vector3d GravityInPalm(double t_s, const Eigen::Vector3d& gravity_world) const;

 private:
  PalmMotionParams params_;
  Eigen::Matrix3d initial_;
  bool turning_ = false;
  Eigen::Vector3d axis_ = Eigen::Vector3d::UnitZ();
  std::vector<std::pair<double, Eigen::Quaterniond>> trajectory_;
};

}  // namespace dmpl
