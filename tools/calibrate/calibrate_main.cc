// dmpl_calibrate: offline calibration with Ceres from recorded LCM logs (tools/dmpl calibrate).
//
//   dmpl_calibrate LOG... [--out FILE] [--report FILE] [--config FILE]
//
// Fits the tactile sensors (force scale and bias, contact-position offset) against the truth
// channels of simulation logs, the object's surface near the contacts from contact positions
// alone, each finger's force response in contact, and chooses the composite controller's force
// PI gains (grip and exploration) on those models. Writes a parameter file that
// `tools/dmpl run ... --params FILE` overlays on an experiment, and a Markdown report of the fits
// (FILE.md unless --report). Missing data is an error that says what is missing; a fit that does
// not converge is reported and nothing is written.
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "components/controller/controller_params.h"
#include "components/runtime/config.h"
#include "tools/calibrate/fits.h"

namespace {

using dmpl::calib::FitResult;

std::string Format(double v) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream os;
  os.precision(5);
  os << v;
  return os.str();
}

void ReportFit(std::ostream& os, const FitResult& fit) {
  os << "## " << fit.name << "\n\n";
  if (!fit.ok) {
    os << "**Did not converge**: " << fit.message << "\n\n";
    return;
  }
  os << "Samples used: " << fit.samples << ". Residual RMS before: " << Format(fit.rms_before)
     << " " << fit.residual_unit << ", after: " << Format(fit.rms_after) << " "
     << fit.residual_unit << ".";
  if (!fit.message.empty()) os << " " << fit.message << ".";
  os << "\n\n| parameter | value | std. dev. | unit |\n| --- | --- | --- | --- |\n";
  for (const auto& p : fit.params) {
    os << "| " << p.name << " | " << Format(p.value) << " | " << Format(p.stddev) << " | "
       << p.unit << " |\n";
  }
  os << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> logs;
  std::string out, report_path, config_path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--out" || arg == "--report" || arg == "--config") && i + 1 < argc) {
      (arg == "--out" ? out : arg == "--report" ? report_path : config_path) = argv[++i];
    } else if (arg == "-h" || arg == "--help") {
      std::cout << "usage: tools/dmpl calibrate LOG... [--out FILE] [--report FILE] "
                   "[--config FILE]\n";
      return 0;
    } else if (arg.rfind("--", 0) == 0) {
      std::cerr << "dmpl calibrate: unknown option '" << arg << "'\n";
      return 2;
    } else {
      logs.push_back(arg);
    }
  }
  if (logs.empty()) {
    std::cerr << "dmpl calibrate: give at least one LOG\n";
    return 2;
  }
  if (out.empty()) out = "calibration.yaml";
  if (report_path.empty()) report_path = out + ".md";
  // The gains the logs were recorded with: the run's config, next to its log.
  if (config_path.empty()) {
    const auto guess = std::filesystem::path(logs.front()).parent_path() / "config.yaml";
    if (std::filesystem::exists(guess)) config_path = guess.string();
  }
  dmpl::ControllerParams current;
  try {
    if (!config_path.empty()) dmpl::Config::Resolve(config_path, {}, {}).Load("controller", &current);
  } catch (const std::exception& e) {
    std::cerr << "dmpl calibrate: " << e.what() << "\n";
    return 2;
  }

  std::vector<FitResult> fits;
  dmpl::calib::PiGains grip, explore;
  try {
    const dmpl::calib::LogData data = dmpl::calib::ReadLogs(logs);
    if (data.ticks.empty() || data.fingers.empty()) {
      throw dmpl::calib::DataError("no DMPL_SENSORS/DMPL_SENSORS_TRUE messages in the logs");
    }
    std::cerr << "dmpl calibrate: " << data.messages << " messages, " << data.ticks.size()
              << " ticks from " << logs.size() << " log(s)\n";
    fits.push_back(dmpl::calib::FitForce(data));
    fits.push_back(dmpl::calib::FitContactOffset(data));
    const FitResult& offset = fits.back();
    const Eigen::Vector3d o(offset.ok ? offset.Get("offset_x") : 0.0,
                            offset.ok ? offset.Get("offset_y") : 0.0,
                            offset.ok ? offset.Get("offset_z") : 0.0);
    fits.push_back(dmpl::calib::FitSurface(data, o));
    std::vector<dmpl::calib::FingerModel> models;
    fits.push_back(dmpl::calib::FitForceResponse(data, &models));
    if (fits.back().ok) {
      fits.push_back(dmpl::calib::ChooseForceGains(
          models, 1e-3, 0.1, current.grip_force_n, {current.force.kp, current.force.ki},
          "grip force PI gains (a step 0.1 N -> grip force on the identified fingers)", &grip));
      fits.push_back(dmpl::calib::ChooseForceGains(
          models, 1e-3, 0.5, current.explore_force_n,
          {current.explore_force.kp, current.explore_force.ki},
          "exploration force PI gains (a step down to the exploration force)", &explore));
    }
  } catch (const std::exception& e) {
    std::cerr << "dmpl calibrate: " << e.what() << "; nothing written\n";
    return 2;
  }

  std::ostringstream report;
  std::time_t now = std::time(nullptr);
  report << "# dmpl calibration\n\nLogs:";
  for (const auto& l : logs) report << " `" << l << "`";
  report << "\n\nDate: " << std::ctime(&now) << "\nGains the logs were recorded with: from `"
         << (config_path.empty() ? std::string("(defaults)") : config_path) << "`.\n\n";
  bool ok = true;
  for (const auto& f : fits) {
    ReportFit(report, f);
    ok = ok && f.ok;
  }
  if (!ok) {
    std::cout << report.str();
    std::cerr << "dmpl calibrate: a fit did not converge (see above); nothing written\n";
    return 1;
  }
  const FitResult& force = fits[0];
  const FitResult& pos = fits[1];
  const FitResult& surface = fits[2];
  std::ofstream yaml(out);
  yaml.precision(6);
  yaml << "# Written by tools/dmpl calibrate from";
  for (const auto& l : logs) yaml << " " << l;
  yaml << "\n# Overlay it on an experiment: tools/dmpl run CONFIG --params " << out << "\n"
       << "controller:\n"
       << "  force: {kp: " << grip.kp << ", ki: " << grip.ki
       << ", integral_limit: " << current.force.integral_limit << "}\n"
       << "  explore_force: {kp: " << explore.kp << ", ki: " << explore.ki
       << ", integral_limit: " << current.explore_force.integral_limit << "}\n"
       << "  # The tactile readings, corrected before use: force = (sensed - bias) / scale,\n"
       << "  # contact point = sensed - offset.\n"
       << "  tactile_force_scale: " << force.Get("force_scale") << "\n"
       << "  tactile_force_bias: " << force.Get("force_bias") << "\n"
       << "  tactile_position_offset: [" << pos.Get("offset_x") << ", " << pos.Get("offset_y")
       << ", " << pos.Get("offset_z") << "]\n"
       << "  # The fitted surface's centre relative to the object estimate (" << surface.message
       << ", radius " << surface.Get("radius") << " m):\n"
       << "  # the force planner may aim there instead of at the contacts' mean.\n"
       << "  surface_centre_offset: [" << surface.Get("centre_from_estimate_x") << ", "
       << surface.Get("centre_from_estimate_y") << ", " << surface.Get("centre_from_estimate_z")
       << "]\n";
  yaml.close();
  std::ofstream(report_path) << report.str();
  std::cout << report.str();
  std::cerr << "dmpl calibrate: wrote " << out << " and " << report_path << "\n";
  return 0;
}
