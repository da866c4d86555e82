#pragma once
// What the calibration reads from recorded LCM logs: per tick, the sensed and the true tactile
// readings, and the controller's targets, tips and desired forces. Pure data; reading it is the
// only place that knows the log format.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace dmpl::calib {

struct TipSample {
  bool in_contact = false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double force = 0.0;
};

struct ControlSample {
  int8_t role = 0;
  int8_t primitive = 0;
  bool in_contact = false;
  double force = 0.0;           // sensed
  double desired = 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
};

struct Tick {
  double t = 0.0;
  bool has_sensed = false, has_truth = false, has_control = false, has_object = false;
  std::vector<TipSample> sensed, truth;  // per finger
  std::vector<ControlSample> control;    // per finger
  Eigen::Vector3d object_position = Eigen::Vector3d::Zero();  // sensed (noisy) estimate
};

struct LogData {
  std::vector<std::string> fingers;
  std::map<int64_t, Tick> ticks;  // by seq, over every log (seqs of later logs are offset)
  std::vector<std::string> sources;
  int64_t messages = 0;
};

// Reads the logs. Throws std::runtime_error naming the file when one cannot be read.
LogData ReadLogs(const std::vector<std::string>& paths);

}  // namespace dmpl::calib
