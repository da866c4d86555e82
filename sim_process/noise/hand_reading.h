#pragma once
// One tick of what the hand's sensors report, as plain values: the noise injector's truth in
// and sensed out. hand_sensors_t translates to and from it (sensors_translation.h); the core
// never sees a message.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dmpl {

struct JointsReading {
  std::vector<std::string> names;
  std::vector<double> position;  // rad
  std::vector<double> velocity;  // rad/s
  std::vector<double> effort;    // N m
};

struct ObjectPoseReading {
  bool valid = true;                                   // false: the camera lost the object
  std::array<double, 3> position = {0, 0, 0};          // m, palm frame
  std::array<double, 4> orientation = {1, 0, 0, 0};    // unit quaternion w, x, y, z
  std::array<double, 3> linear_velocity = {0, 0, 0};   // m/s (truth only)
  std::array<double, 3> angular_velocity = {0, 0, 0};  // rad/s (truth only)
};

struct TipReading {
  std::string finger;
  bool in_contact = false;
  std::array<double, 3> position = {0, 0, 0};  // contact point, m
  std::array<double, 3> normal = {0, 0, 0};    // from the object into the fingertip
  double force_n = 0.0;
  int num_points = 0;
};

struct HandReading {
  int64_t seq = 0;    // the tick
  int64_t utime = 0;  // its simulated time, us
  JointsReading joints;
  ObjectPoseReading object;
  std::vector<TipReading> tips;
  std::array<double, 3> gravity = {0, 0, 0};  // m/s^2, palm frame (an IMU on the palm)
};

}  // namespace dmpl
