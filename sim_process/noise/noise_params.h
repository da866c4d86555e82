#pragma once
#include <array>

#include "components/runtime/params.h"

namespace dmpl {

// Section `noise`: what turns ground truth into sensed channels. Defaults: the paper's 0.5 cm
// Gaussian noise on the object position, everything else exact.
struct NoiseParams {
  double object_position_sigma = 0.005;      // m, per axis
  double object_orientation_sigma = 0.0;     // rad, per axis of a small random rotation
  double joint_position_sigma = 0.0;         // rad
  double joint_velocity_sigma = 0.0;         // rad/s
  double contact_position_sigma = 0.0;       // m, per axis, while in contact
  std::array<double, 3> contact_position_offset = {0.0, 0.0, 0.0};  // m, a miscalibration
  double force_sigma = 0.0;                  // N, while in contact
  double force_bias = 0.0;                   // N: sensed = scale * true + bias + noise
  double force_scale = 1.0;
  double dropout_probability = 0.0;          // per message: the reading is lost this tick
  int delay_ticks = 0;                       // sensed(k) carries truth(k - delay)
  // The palm IMU's gravity: its direction turned by a small random rotation of this many rad per
  // axis, each tick (a MEMS accelerometer at rest: ~0.005 rad); never delayed or dropped.
  double gravity_direction_sigma = 0.0;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(object_position_sigma), AtLeast(0));
    a->Visit(DMPL_NVP(object_orientation_sigma), AtLeast(0));
    a->Visit(DMPL_NVP(joint_position_sigma), AtLeast(0));
    a->Visit(DMPL_NVP(joint_velocity_sigma), AtLeast(0));
    a->Visit(DMPL_NVP(contact_position_sigma), AtLeast(0));
    a->Visit(DMPL_NVP(contact_position_offset));
    a->Visit(DMPL_NVP(force_sigma), AtLeast(0));
    a->Visit(DMPL_NVP(force_bias));
    a->Visit(DMPL_NVP(force_scale), Above(0));
    a->Visit(DMPL_NVP(dropout_probability), InRange(0, 1));
    a->Visit(DMPL_NVP(delay_ticks), InRange(0, 1000));
    a->Visit(DMPL_NVP(gravity_direction_sigma), InRange(0, 0.5));
  }

  // Throws ConfigError on values that make no sense (negative sigma, probability > 1, ...).
  void Validate(const std::string& source) const { CheckBounds(*this, source, "noise"); }
};

}  // namespace dmpl
