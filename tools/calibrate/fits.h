#pragma once
// The calibration's fits (Ceres, offline only):
//  - tactile force: sensed = scale * true + bias (robust: slips and contact changes are outliers)
//  - tactile contact position: sensed = true + offset (robust)
//  - the object's surface near the contacts, from contact positions alone: a sphere (centre,
//    radius) or a cylinder (axis, radius)
//  - each finger's force response in contact: F' = F + a (K d - F), d the commanded penetration
//  - the composite controller's force PI gains (and the exploration's) that minimise tracking
//    error plus effort on the identified models, under a stability margin.
// Each returns a FitResult that says whether it converged, with values, standard deviations
// (Ceres covariance), residuals before and after, and how much data it used.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tools/calibrate/log_data.h"

namespace dmpl::calib {

struct Estimate {
  std::string name;
  double value = 0.0;
  double stddev = 0.0;  // NaN when the covariance could not be computed
  std::string unit;
};

struct FitResult {
  std::string name;
  bool ok = false;
  std::string message;  // why it failed, or a remark
  int samples = 0;
  double rms_before = 0.0, rms_after = 0.0;
  std::string residual_unit;
  std::vector<Estimate> params;
  double Get(const std::string& name) const;
};

// Thrown for data that cannot support a fit (missing channels, too few samples, no excitation).
class DataError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

FitResult FitForce(const LogData& data);
FitResult FitContactOffset(const LogData& data);
// `offset`: the contact-position offset to remove first (from FitContactOffset).
FitResult FitSurface(const LogData& data, const Eigen::Vector3d& offset);

struct FingerModel {
  std::string finger;
  double stiffness = 0.0;  // N/m along the contact direction
  double rate = 0.0;       // a: share of the force error closed per tick
};
FitResult FitForceResponse(const LogData& data, std::vector<FingerModel>* models);

struct PiGains {
  double kp = 0.0, ki = 0.0;
};
// Chooses PI gains on the models for a step of the desired force from `from` to `to` (N).
FitResult ChooseForceGains(const std::vector<FingerModel>& models, double dt, double from,
                           double to, const PiGains& current, const std::string& name,
                           PiGains* chosen);

}  // namespace dmpl::calib
