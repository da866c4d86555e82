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
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "components/controller/controller_params.h"
#include "components/runtime/command_line.h"
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

struct CommandLine {
  std::vector<std::string> logs;
  std::string out, report_path, config_path;
};

// Parses the command line into `cl`; the exit code when the process is to exit now.
std::optional<int> ParseCommandLine(int argc, char** argv, CommandLine* cl) {
  CLI::App app{"dmpl calibrate: tactile sensors, object surface, finger force response and force "
               "PI gains, fitted with Ceres from recorded logs",
               "dmpl calibrate"};
  app.add_option("LOG", cl->logs, "recorded LCM logs of simulation runs")->required();
  app.add_option("--out", cl->out, "the parameter overlay written (default calibration.yaml)")
      ->type_name("FILE");
  app.add_option("--report", cl->report_path, "the Markdown report written (default FILE.md)")
      ->type_name("FILE");
  app.add_option("--config", cl->config_path,
                 "the config the logs were recorded with (default: config.yaml next to the "
                 "first LOG)")
      ->type_name("FILE");
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return code;
  if (cl->out.empty()) cl->out = "calibration.yaml";
  if (cl->report_path.empty()) cl->report_path = cl->out + ".md";
  // The gains the logs were recorded with: the run's config, next to its log.
  if (cl->config_path.empty()) {
    const auto guess = std::filesystem::path(cl->logs.front()).parent_path() / "config.yaml";
    if (std::filesystem::exists(guess)) cl->config_path = guess.string();
  }
  return std::nullopt;
}

// Every fit, in the order the overlay reads them: force, contact offset, surface, then (when the
// force response was identified) the grip and exploration gains chosen on it.
struct Fits {
  std::vector<FitResult> results;
  dmpl::calib::PiGains grip, explore;
  bool ok() const {
    for (const auto& f : results) {
      if (!f.ok) return false;
    }
    return true;
  }
};

Fits RunFits(const std::vector<std::string>& logs, const dmpl::ControllerParams& current) {
  Fits fits;
  const dmpl::calib::LogData data = dmpl::calib::ReadLogs(logs);
  if (data.ticks.empty() || data.fingers.empty()) {
    throw dmpl::calib::DataError("no DMPL_SENSORS/DMPL_SENSORS_TRUE messages in the logs");
  }
  std::cerr << "dmpl calibrate: " << data.messages << " messages, " << data.ticks.size()
            << " ticks from " << logs.size() << " log(s)\n";
  auto& r = fits.results;
  r.push_back(dmpl::calib::FitForce(data));
  r.push_back(dmpl::calib::FitContactOffset(data));
  const FitResult& offset = r.back();
  const Eigen::Vector3d o(offset.ok ? offset.Get("offset_x") : 0.0,
                          offset.ok ? offset.Get("offset_y") : 0.0,
                          offset.ok ? offset.Get("offset_z") : 0.0);
  r.push_back(dmpl::calib::FitSurface(data, o));
  std::vector<dmpl::calib::FingerModel> models;
  r.push_back(dmpl::calib::FitForceResponse(data, &models));
  if (r.back().ok) {
    r.push_back(dmpl::calib::ChooseForceGains(
        models, 1e-3, 0.1, current.grip_force_n, {current.force.kp, current.force.ki},
        "grip force PI gains (a step 0.1 N -> grip force on the identified fingers)", &fits.grip));
    r.push_back(dmpl::calib::ChooseForceGains(
        models, 1e-3, 0.5, current.explore_force_n,
        {current.explore_force.kp, current.explore_force.ki},
        "exploration force PI gains (a step down to the exploration force)", &fits.explore));
  }
  return fits;
}

std::string Report(const CommandLine& cl, const Fits& fits) {
  std::ostringstream report;
  std::time_t now = std::time(nullptr);
  report << "# dmpl calibration\n\nLogs:";
  for (const auto& l : cl.logs) report << " `" << l << "`";
  report << "\n\nDate: " << std::ctime(&now) << "\nGains the logs were recorded with: from `"
         << (cl.config_path.empty() ? std::string("(defaults)") : cl.config_path) << "`.\n\n";
  for (const auto& f : fits.results) ReportFit(report, f);
  return report.str();
}

// The overlay a run takes with --params.
std::string Overlay(const CommandLine& cl, const Fits& fits, const dmpl::ControllerParams& current) {
  const FitResult& force = fits.results[0];
  const FitResult& pos = fits.results[1];
  const FitResult& surface = fits.results[2];
  std::ostringstream yaml;
  yaml.precision(6);
  yaml << "# Written by tools/dmpl calibrate from";
  for (const auto& l : cl.logs) yaml << " " << l;
  yaml << "\n# Overlay it on an experiment: tools/dmpl run CONFIG --params " << cl.out << "\n"
       << "controller:\n"
       << "  force: {kp: " << fits.grip.kp << ", ki: " << fits.grip.ki
       << ", integral_limit: " << current.force.integral_limit << "}\n"
       << "  explore_force: {kp: " << fits.explore.kp << ", ki: " << fits.explore.ki
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
  return yaml.str();
}

bool WriteFile(const std::string& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  file.close();
  if (file) return true;
  std::cerr << "dmpl calibrate: cannot write " << path << ": " << std::strerror(errno) << "\n";
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  CommandLine cl;
  if (const auto code = ParseCommandLine(argc, argv, &cl)) return *code;
  dmpl::ControllerParams current;
  Fits fits;
  try {
    if (!cl.config_path.empty()) {
      dmpl::Config::Resolve(cl.config_path, {}, {}).Load("controller", &current);
    }
    fits = RunFits(cl.logs, current);
  } catch (const std::exception& e) {
    std::cerr << "dmpl calibrate: " << e.what() << "; nothing written\n";
    return 2;
  }
  const std::string report = Report(cl, fits);
  std::cout << report;
  if (!fits.ok()) {
    std::cerr << "dmpl calibrate: a fit did not converge (see above); nothing written\n";
    return 1;
  }
  if (!WriteFile(cl.out, Overlay(cl, fits, current)) || !WriteFile(cl.report_path, report)) {
    return 2;
  }
  std::cerr << "dmpl calibrate: wrote " << cl.out << " and " << cl.report_path << "\n";
  return 0;
}
