#include "tools/calibrate/fits.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <ceres/ceres.h>

namespace dmpl::calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kMinSamples = 200;

double Rms(const std::vector<double>& r) {
  if (r.empty()) return 0.0;
  double s = 0.0;
  for (double x : r) s += x * x;
  return std::sqrt(s / r.size());
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + i, v.end());
  return v[i];
}

bool Solve(ceres::Problem* problem, FitResult* result, int max_iterations = 200) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  if (summary.termination_type != ceres::CONVERGENCE || !summary.IsSolutionUsable()) {
    result->ok = false;
    result->message = "did not converge: " + summary.message;
    return false;
  }
  result->ok = true;
  return true;
}

// Standard deviations of one parameter block: Ceres' covariance, (J^T J)^-1, assumes residuals of
// unit variance; scaled here by the residuals' own variance. NaN when rank deficient.
std::vector<double> StdDevs(ceres::Problem* problem, double* block, int size) {
  double cost = 0.0;
  problem->Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
  const int dof = std::max(1, problem->NumResiduals() - problem->NumParameters());
  const double sigma2 = 2.0 * cost / dof;
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.null_space_rank = -1;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks = {{block, block}};
  std::vector<double> out(size, kNaN);
  if (!covariance.Compute(blocks, problem)) return out;
  std::vector<double> c(size * size);
  if (!covariance.GetCovarianceBlock(block, block, c.data())) return out;
  for (int i = 0; i < size; ++i) out[i] = std::sqrt(std::max(0.0, c[i * size + i]) * sigma2);
  return out;
}

struct ForceResidual {
  double truth, sensed;
  template <typename T>
  bool operator()(const T* p, T* r) const {
    r[0] = T(sensed) - (p[0] * T(truth) + p[1]);
    return true;
  }
};

struct OffsetResidual {
  Eigen::Vector3d truth, sensed;
  template <typename T>
  bool operator()(const T* o, T* r) const {
    for (int i = 0; i < 3; ++i) r[i] = T(sensed[i]) - (T(truth[i]) + o[i]);
    return true;
  }
};

struct SphereResidual {
  Eigen::Vector3d p;
  template <typename T>
  bool operator()(const T* c, const T* radius, T* r) const {
    const T dx = T(p.x()) - c[0], dy = T(p.y()) - c[1], dz = T(p.z()) - c[2];
    r[0] = ceres::sqrt(dx * dx + dy * dy + dz * dz) - radius[0];
    return true;
  }
};

struct CylinderResidual {
  Eigen::Vector3d p;
  template <typename T>
  bool operator()(const T* c, const T* axis, const T* radius, T* r) const {
    T d[3] = {T(p.x()) - c[0], T(p.y()) - c[1], T(p.z()) - c[2]};
    const T along = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
    T perp2 = T(0);
    for (int i = 0; i < 3; ++i) {
      const T q = d[i] - along * axis[i];
      perp2 += q * q;
    }
    r[0] = ceres::sqrt(perp2 + T(1e-18)) - radius[0];
    return true;
  }
};

constexpr int kWindow = 100;  // ticks of one output-error window

// Output error over a window: the model F' = F + a (K d - F) run on the recorded commanded
// penetrations from the recorded first force, against the recorded forces. Unlike one-step
// prediction, noise in the force cannot hide the dynamics.
struct ResponseWindow {
  std::array<double, kWindow> force, d;
  template <typename T>
  bool operator()(const T* p, T* r) const {
    T f = T(force[0]);
    for (int k = 0; k < kWindow; ++k) {
      r[k] = T(force[k]) - f;
      f = f + p[1] * (p[0] * T(d[k]) - f);
    }
    return true;
  }
};

}  // namespace

double FitResult::Get(const std::string& n) const {
  for (const auto& p : params) {
    if (p.name == n) return p.value;
  }
  return kNaN;
}

FitResult FitForce(const LogData& data) {
  FitResult result;
  result.name = "tactile force: sensed = scale * true + bias";
  result.residual_unit = "N";
  std::vector<std::pair<double, double>> samples;  // (true, sensed)
  for (const auto& [seq, tick] : data.ticks) {
    if (!tick.has_sensed || !tick.has_truth) continue;
    for (size_t f = 0; f < tick.truth.size() && f < tick.sensed.size(); ++f) {
      if (tick.truth[f].in_contact && tick.sensed[f].in_contact && tick.truth[f].force > 0.05) {
        samples.emplace_back(tick.truth[f].force, tick.sensed[f].force);
      }
    }
  }
  if (samples.size() < kMinSamples) {
    throw DataError("tactile force: " + std::to_string(samples.size()) +
                    " contact samples with both DMPL_SENSORS and DMPL_SENSORS_TRUE; need at least " +
                    std::to_string(kMinSamples));
  }
  std::vector<double> truth;
  for (const auto& s : samples) truth.push_back(s.first);
  const double range = Quantile(truth, 0.95) - Quantile(truth, 0.05);
  if (range < 0.2) {
    throw DataError("tactile force: no excitation: the true force spans only " +
                    std::to_string(range) + " N (need 0.2 N) so scale and bias cannot be told apart");
  }
  double p[2] = {1.0, 0.0};
  ceres::Problem problem;
  std::vector<double> before, after;
  for (const auto& [t, s] : samples) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<ForceResidual, 1, 2>(new ForceResidual{t, s}),
        new ceres::HuberLoss(0.05), p);
    before.push_back(s - t);
  }
  result.samples = static_cast<int>(samples.size());
  if (!Solve(&problem, &result)) return result;
  for (const auto& [t, s] : samples) after.push_back(s - (p[0] * t + p[1]));
  const auto sd = StdDevs(&problem, p, 2);
  result.params = {{"force_scale", p[0], sd[0], ""}, {"force_bias", p[1], sd[1], "N"}};
  result.rms_before = Rms(before);
  result.rms_after = Rms(after);
  return result;
}

FitResult FitContactOffset(const LogData& data) {
  FitResult result;
  result.name = "tactile contact position: sensed = true + offset";
  result.residual_unit = "m";
  double o[3] = {0, 0, 0};
  ceres::Problem problem;
  std::vector<double> before, after;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> samples;
  for (const auto& [seq, tick] : data.ticks) {
    if (!tick.has_sensed || !tick.has_truth) continue;
    for (size_t f = 0; f < tick.truth.size() && f < tick.sensed.size(); ++f) {
      if (tick.truth[f].in_contact && tick.sensed[f].in_contact && tick.truth[f].force > 0.05) {
        samples.emplace_back(tick.truth[f].position, tick.sensed[f].position);
      }
    }
  }
  if (samples.size() < kMinSamples) {
    throw DataError("contact position: " + std::to_string(samples.size()) +
                    " contact samples with both DMPL_SENSORS and DMPL_SENSORS_TRUE; need at least " +
                    std::to_string(kMinSamples));
  }
  for (const auto& [t, s] : samples) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<OffsetResidual, 3, 3>(new OffsetResidual{t, s}),
        new ceres::HuberLoss(0.002), o);
    before.push_back((s - t).norm());
  }
  result.samples = static_cast<int>(samples.size());
  if (!Solve(&problem, &result)) return result;
  const Eigen::Vector3d off(o[0], o[1], o[2]);
  for (const auto& [t, s] : samples) after.push_back((s - t - off).norm());
  const auto sd = StdDevs(&problem, o, 3);
  result.params = {{"offset_x", o[0], sd[0], "m"}, {"offset_y", o[1], sd[1], "m"},
                   {"offset_z", o[2], sd[2], "m"}};
  result.rms_before = Rms(before);
  result.rms_after = Rms(after);
  return result;
}

// One shape fitted to the contact points: its parameters (with standard deviations) and each
// point's distance from its surface.
struct ShapeFit {
  bool ok = false;
  std::vector<Estimate> params;
  std::vector<double> residuals;
};

ShapeFit FitSphereTo(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& start,
                     double start_radius) {
  double c[3] = {start.x(), start.y(), start.z()}, r = start_radius;
  ceres::Problem problem;
  for (const auto& p : points) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<SphereResidual, 1, 3, 1>(new SphereResidual{p}),
        new ceres::CauchyLoss(0.002), c, &r);
  }
  FitResult solved;
  ShapeFit fit;
  fit.ok = Solve(&problem, &solved);
  const Eigen::Vector3d centre(c[0], c[1], c[2]);
  for (const auto& p : points) fit.residuals.push_back((p - centre).norm() - r);
  if (!fit.ok) return fit;
  const auto sd = StdDevs(&problem, c, 3);
  const auto sr = StdDevs(&problem, &r, 1);
  fit.params = {{"centre_x", c[0], sd[0], "m"}, {"centre_y", c[1], sd[1], "m"},
                {"centre_z", c[2], sd[2], "m"}, {"radius", r, sr[0], "m"}};
  return fit;
}

// `axis`: where the axis starts (the normal of the points' best plane).
ShapeFit FitCylinderTo(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& start,
                       const Eigen::Vector3d& start_axis, double start_radius) {
  double c[3] = {start.x(), start.y(), start.z()};
  double axis[3] = {start_axis.x(), start_axis.y(), start_axis.z()}, r = start_radius;
  ceres::Problem problem;
  for (const auto& p : points) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<CylinderResidual, 1, 3, 3, 1>(new CylinderResidual{p}),
        new ceres::CauchyLoss(0.002), c, axis, &r);
  }
  problem.SetManifold(axis, new ceres::SphereManifold<3>());
  FitResult solved;
  ShapeFit fit;
  fit.ok = Solve(&problem, &solved);
  const Eigen::Vector3d a(axis[0], axis[1], axis[2]), c0(c[0], c[1], c[2]);
  for (const auto& p : points) {
    const Eigen::Vector3d d = p - c0;
    fit.residuals.push_back((d - d.dot(a) * a).norm() - r);
  }
  if (!fit.ok) return fit;
  const auto sd = StdDevs(&problem, c, 3);
  const auto sr = StdDevs(&problem, &r, 1);
  fit.params = {{"centre_x", c[0], sd[0], "m"}, {"centre_y", c[1], sd[1], "m"},
                {"centre_z", c[2], sd[2], "m"}, {"radius", r, sr[0], "m"},
                {"axis_x", axis[0], kNaN, ""},  {"axis_y", axis[1], kNaN, ""},
                {"axis_z", axis[2], kNaN, ""}};
  return fit;
}

FitResult FitSurface(const LogData& data, const Eigen::Vector3d& offset) {
  FitResult result;
  result.name = "object surface from contact positions (sphere or cylinder)";
  result.residual_unit = "m";
  // The firm contacts' points (offset corrected), and the object estimate while they were made.
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d object_mean = Eigen::Vector3d::Zero();
  int object_samples = 0;
  for (const auto& [seq, tick] : data.ticks) {
    if (!tick.has_sensed) continue;
    bool any = false;
    for (const auto& s : tick.sensed) {
      if (s.in_contact && s.force > 0.2) {
        points.push_back(s.position - offset);
        any = true;
      }
    }
    if (any && tick.has_object) {
      object_mean += tick.object_position;
      ++object_samples;
    }
  }
  if (points.size() < kMinSamples) {
    throw DataError("surface: " + std::to_string(points.size()) +
                    " contact points on DMPL_SENSORS; need at least " + std::to_string(kMinSamples));
  }
  if (object_samples > 0) object_mean /= object_samples;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= points.size();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / points.size());
  if (eig.eigenvalues()(1) < 1e-6) {
    throw DataError("surface: the contact points lie on a line (spread " +
                    std::to_string(std::sqrt(eig.eigenvalues()(1))) +
                    " m); a surface cannot be fitted");
  }
  double mean_dist = 0;
  for (const auto& p : points) mean_dist += (p - mean).norm();
  mean_dist /= points.size();

  const ShapeFit sphere = FitSphereTo(points, mean, mean_dist);
  const ShapeFit cylinder = FitCylinderTo(points, mean, eig.eigenvectors().col(0), mean_dist);
  if (!sphere.ok && !cylinder.ok) {
    result.ok = false;
    result.message = "neither a sphere nor a cylinder fit converged";
    return result;
  }
  std::vector<double> before;
  for (const auto& p : points) before.push_back((p - mean).norm() - mean_dist);
  result.samples = static_cast<int>(points.size());
  result.rms_before = Rms(before);  // the raw contact mean as the centre
  result.ok = true;
  // Contacts around one circle (a plane of points) fit spheres of any radius centred on its axis:
  // only the circle's centre is determined, which the cylinder fit gives. Otherwise prefer the
  // sphere (one parameter fewer) unless the cylinder is clearly better.
  const double sphere_rms = Rms(sphere.residuals), cylinder_rms = Rms(cylinder.residuals);
  const bool planar = std::sqrt(eig.eigenvalues()(0)) < 0.2 * std::sqrt(eig.eigenvalues()(1));
  const bool use_sphere =
      sphere.ok && !planar && (!cylinder.ok || sphere_rms <= 1.2 * cylinder_rms);
  if (!use_sphere && !cylinder.ok) {
    result.ok = false;
    result.message = "the contacts lie around one circle and the cylinder fit did not converge";
    return result;
  }
  const ShapeFit& chosen = use_sphere ? sphere : cylinder;
  result.message = use_sphere ? "sphere (cylinder rms " + std::to_string(cylinder_rms) + " m)"
                   : planar   ? "the contacts lie around one circle: its centre and radius (a "
                                "sphere or a cylinder alike)"
                              : "cylinder (sphere rms " + std::to_string(sphere_rms) + " m)";
  result.rms_after = Rms(chosen.residuals);
  result.params = chosen.params;
  const Eigen::Vector3d centre(result.Get("centre_x"), result.Get("centre_y"),
                               result.Get("centre_z"));
  const Eigen::Vector3d rel = centre - object_mean;
  result.params.push_back({"centre_from_estimate_x", rel.x(), kNaN, "m"});
  result.params.push_back({"centre_from_estimate_y", rel.y(), kNaN, "m"});
  result.params.push_back({"centre_from_estimate_z", rel.z(), kNaN, "m"});
  return result;
}

FitResult FitForceResponse(const LogData& data, std::vector<FingerModel>* models) {
  FitResult result;
  result.name = "fingertip force response in contact: F' = F + a (K d - F)";
  result.residual_unit = "N";
  models->clear();
  const int nf = static_cast<int>(data.fingers.size());
  const bool any_control = std::any_of(data.ticks.begin(), data.ticks.end(),
                                       [](const auto& t) { return t.second.has_control; });
  if (nf == 0 || !any_control) {
    throw DataError("force response: the logs have no DMPL_CONTROLLER_STATUS (the controller's "
                    "targets and tips); record a run with the controller");
  }
  std::vector<double> before, after;
  std::string unidentified;  // fingers whose model ended at its bounds
  constexpr double kMinStiffness = 1.0;  // N/m
  constexpr double kMinRate = 1e-4;      // per tick
  for (int f = 0; f < nf; ++f) {
    // Runs of consecutive ticks in composite grip and contact, cut into windows.
    std::vector<ResponseWindow> windows;
    ResponseWindow w;
    int n = 0;
    int64_t prev_seq = -10;
    std::vector<double> ds;
    for (const auto& [seq, tick] : data.ticks) {
      const bool usable = tick.has_control && static_cast<int>(tick.control.size()) > f &&
                          tick.control[f].primitive == 2 && tick.control[f].in_contact &&
                          tick.control[f].force > 0.05;
      if (!usable || seq != prev_seq + 1) n = 0;
      prev_seq = seq;
      if (!usable) continue;
      const ControlSample& c = tick.control[f];
      const double d = (c.target - c.tip).dot((c.contact - c.tip).normalized());
      if (!std::isfinite(d)) {
        n = 0;
        continue;
      }
      w.force[n] = c.force;
      w.d[n] = d;
      ds.push_back(d);
      if (++n == kWindow) {
        windows.push_back(w);
        n = 0;
      }
    }
    if (windows.size() < 10) {
      throw DataError("force response of finger " + data.fingers[f] + ": " +
                      std::to_string(windows.size() * kWindow) +
                      " consecutive composite-grip samples on DMPL_CONTROLLER_STATUS; need " +
                      std::to_string(10 * kWindow) +
                      " (a log recorded with the analysis policy keeps 100 of every 1000 ticks "
                      "of it: record a longer run, or with --record full)");
    }
    const double spread = Quantile(ds, 0.95) - Quantile(ds, 0.05);
    if (spread < 2e-4) {
      throw DataError("force response of finger " + data.fingers[f] +
                      ": no excitation (commanded penetration spans " + std::to_string(spread) +
                      " m, need 0.2 mm)");
    }
    double p[2] = {300.0, 0.05};
    ceres::Problem problem;
    for (const auto& win : windows) {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ResponseWindow, kWindow, 2>(new ResponseWindow(win)),
          new ceres::HuberLoss(0.1), p);
      for (int k = 0; k < kWindow; ++k) before.push_back(win.force[k] - win.force[0]);
    }
    problem.SetParameterLowerBound(p, 0, kMinStiffness);
    problem.SetParameterLowerBound(p, 1, kMinRate);
    problem.SetParameterUpperBound(p, 1, 1.0);
    FitResult one;
    if (!Solve(&problem, &one)) {
      result.ok = false;
      result.message = "finger " + data.fingers[f] + ": " + one.message;
      return result;
    }
    for (const auto& window : windows) {
      std::array<double, kWindow> r;
      window(p, r.data());
      after.insert(after.end(), r.begin(), r.end());
    }
    const auto sd = StdDevs(&problem, p, 2);
    result.params.push_back({data.fingers[f] + "_stiffness", p[0], sd[0], "N/m"});
    result.params.push_back({data.fingers[f] + "_rate", p[1], sd[1], "per tick"});
    result.samples += static_cast<int>(windows.size()) * kWindow;
    // A model at its bounds says the finger's force did not follow its commands in these
    // windows (it pressed on something other than its sensor, say): it cannot tell the gains
    // anything, so the gains are chosen on the others.
    if (p[0] <= kMinStiffness * (1 + 1e-6) || p[1] <= kMinRate * (1 + 1e-6)) {
      unidentified += (unidentified.empty() ? "" : ", ") + data.fingers[f];
      continue;
    }
    models->push_back({data.fingers[f], p[0], p[1]});
  }
  result.rms_before = Rms(before);
  result.rms_after = Rms(after);
  result.message = "output error over windows of " + std::to_string(kWindow) +
                   " ticks; before: the force held at the window's first value";
  if (!unidentified.empty()) {
    result.message += "; not identified (a model at its bounds), left out of the gains: " +
                      unidentified;
  }
  result.ok = !models->empty();
  if (!result.ok) result.message = "no finger's force response was identified: " + unidentified;
  return result;
}

namespace {

constexpr int kSteps = 600;  // 0.6 s of a force step at 1 kHz

// Closed loop of the PI force term on one identified finger: d = kp e + I, I' = I + ki e dt,
// F' = F + a (K d - F). Fills residuals: tracking error, effort (force change the command asks
// per tick) and overshoot, each scaled by sqrt(dt) so the cost is an integral over time.
void SimulateStep(const FingerModel& m, double kp, double ki, double dt, double from, double to,
                  double* residuals) {
  // At rest at `from` before the step; the command acts one tick late (a margin for the servo's
  // dynamics, which the first-order model leaves out).
  double force = from, integral = from / m.stiffness;
  double d_prev = integral, d_applied = integral;
  const double w = std::sqrt(dt);
  for (int k = 0; k < kSteps; ++k) {
    const double e = to - force;
    integral += ki * e * dt;
    const double d = kp * e + integral;
    force += m.rate * (m.stiffness * d_applied - force);
    d_applied = d;
    residuals[3 * k] = e * w;
    residuals[3 * k + 1] = 0.05 * m.stiffness * (d - d_prev) * w / dt * 1e-3;
    residuals[3 * k + 2] = 3.0 * std::max(0.0, (force - to) * (to > from ? 1 : -1)) * w;
    d_prev = d;
  }
}

// The closed loop's state (F, I, d applied) evolves by this matrix (the step input aside).
double SpectralRadius(const FingerModel& m, double kp, double ki, double dt) {
  Eigen::Matrix3d a;
  a << 1.0 - m.rate, 0.0, m.rate * m.stiffness,  //
      -ki * dt, 1.0, 0.0,                          //
      -kp - ki * dt, 1.0, 0.0;
  return a.eigenvalues().cwiseAbs().maxCoeff();
}

constexpr double kMaxSpectralRadius = 0.9999;  // stable (the plants themselves are slow)
constexpr double kMaxLoopGain = 1.0;

struct GainCost {
  std::vector<FingerModel> models;
  double dt, from, to;
  bool operator()(double const* const* params, double* residuals) const {
    const double kp = std::exp(params[0][0]), ki = std::exp(params[0][1]);
    for (size_t i = 0; i < models.size(); ++i) {
      SimulateStep(models[i], kp, ki, dt, from, to, residuals + i * 3 * kSteps);
    }
    double worst = 0.0, gain = 0.0;
    for (const auto& m : models) {
      worst = std::max(worst, SpectralRadius(m, kp, ki, dt));
      gain = std::max(gain, kp * m.stiffness);
    }
    residuals[models.size() * 3 * kSteps] = 100.0 * std::max(0.0, worst - kMaxSpectralRadius);
    // The proportional loop gain stays below kMaxLoopGain: the servo's second-order dynamics
    // turn a larger one into ringing the model cannot show.
    residuals[models.size() * 3 * kSteps + 1] = 100.0 * std::max(0.0, gain - kMaxLoopGain);
    return true;
  }
  int size() const { return static_cast<int>(models.size()) * 3 * kSteps + 2; }
  double Cost(double kp, double ki) const {
    std::vector<double> r(size());
    const double p[2] = {std::log(kp), std::log(ki)};
    const double* pp[1] = {p};
    (*this)(pp, r.data());
    double c = 0;
    for (double x : r) c += x * x;
    return 0.5 * c;
  }
};

}  // namespace

FitResult ChooseForceGains(const std::vector<FingerModel>& models, double dt, double from,
                           double to, const PiGains& current, const std::string& name,
                           PiGains* chosen) {
  FitResult result;
  result.name = name;
  result.residual_unit = "cost";
  if (models.empty()) throw DataError(name + ": no finger models to choose gains on");
  GainCost cost{models, dt, from, to};
  auto* fn = new ceres::DynamicNumericDiffCostFunction<GainCost>(new GainCost(cost));
  fn->AddParameterBlock(2);
  fn->SetNumResiduals(cost.size());
  double p[2] = {std::log(current.kp), std::log(current.ki)};
  ceres::Problem problem;
  problem.AddResidualBlock(fn, nullptr, p);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable() || summary.termination_type == ceres::FAILURE) {
    result.ok = false;
    result.message = "did not converge: " + summary.message;
    return result;
  }
  chosen->kp = std::exp(p[0]);
  chosen->ki = std::exp(p[1]);
  double worst = 0.0, gain = 0.0;
  for (const auto& m : models) {
    worst = std::max(worst, SpectralRadius(m, chosen->kp, chosen->ki, dt));
    gain = std::max(gain, chosen->kp * m.stiffness);
  }
  if (worst > kMaxSpectralRadius || gain > 1.05 * kMaxLoopGain) {
    result.ok = false;
    result.message = "the best gains found miss the stability margins (spectral radius " +
                     std::to_string(worst) + ", loop gain " + std::to_string(gain) + ")";
    return result;
  }
  result.ok = true;
  result.samples = static_cast<int>(models.size());
  result.rms_before = cost.Cost(current.kp, current.ki);
  result.rms_after = cost.Cost(chosen->kp, chosen->ki);
  result.message = "cost of the current gains -> the chosen ones; worst closed-loop spectral "
                   "radius " + std::to_string(worst) + " (margin " +
                   std::to_string(kMaxSpectralRadius) + "), largest loop gain kp K " +
                   std::to_string(gain) + " (margin " + std::to_string(kMaxLoopGain) + ")";
  result.params = {{"kp", chosen->kp, kNaN, "m/N"}, {"ki", chosen->ki, kNaN, "m/(N s)"}};
  return result;
}

}  // namespace dmpl::calib
