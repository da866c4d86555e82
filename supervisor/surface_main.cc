// dmpl_surface LOG: what the supervisor learned of the object's surface by touch in a recorded
// run, as JSON on stdout. It feeds the controller's statuses of the log (their sensed contact
// points, tip centres and object estimates) through the supervisor's own Blackboard::LearnSurface,
// so the picture is the model the gait planned on, not a second implementation of it: the
// contacts kept (object frame: point, outward normal, time), the surface along directions
// spread over the sphere (known, distance, normal, uncertainty) and the edges the fingertips
// rolled over (edge_detector.h: finger, time, point, the normals either side). Exit 2 with one message on a
// log it cannot read.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "components/logging/decode.h"
#include "components/logging/event_log_reader.h"
#include "components/runtime/channels.h"
#include "components/runtime/command_line.h"
#include "dmpl/controller_status_t.hpp"
#include "supervisor/blackboard.h"
#include "supervisor/supervisor_translation.h"

namespace {

void PrintVector(const char* key, const Eigen::Vector3d& v) {
  std::printf("\"%s\": [%.6g, %.6g, %.6g]", key, v.x(), v.y(), v.z());
}

// Directions spread evenly over the sphere (a Fibonacci lattice).
std::vector<Eigen::Vector3d> Directions(int n) {
  std::vector<Eigen::Vector3d> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return out;
}

void Print(const dmpl::Blackboard& board, int messages, int directions) {
  std::printf("{\"statuses\": %d, \"tip_radius_m\": %.6g,\n\"contacts\": [", messages,
              board.tip_radius_m);
  const auto& contacts = board.surface.contacts();
  for (size_t i = 0; i < contacts.size(); ++i) {
    std::printf("%s\n  {", i ? "," : "");
    PrintVector("point", contacts[i].point);
    std::printf(", ");
    PrintVector("normal", contacts[i].normal);
    std::printf(", \"time_s\": %.4f}", contacts[i].time_s);
  }
  std::printf("],\n\"along\": [");
  const std::vector<Eigen::Vector3d> dirs = Directions(directions);
  for (size_t i = 0; i < dirs.size(); ++i) {
    const dmpl::SurfacePoint s = board.surface.Along(dirs[i]);
    std::printf("%s\n  {", i ? "," : "");
    PrintVector("direction", dirs[i]);
    std::printf(", \"known\": %s, \"distance_m\": %.6g, \"sigma_m\": %.6g, \"support\": %.4g, ",
                s.known ? "true" : "false", s.distance_m, s.sigma_m, s.support);
    PrintVector("normal", s.normal);
    std::printf("}");
  }
  std::printf("],\n\"edges\": [");
  for (size_t i = 0; i < board.edges.size(); ++i) {
    const dmpl::Edge& e = board.edges[i].edge;
    std::printf("%s\n  {\"finger\": \"%s\", \"time_s\": %.4f, \"angle_rad\": %.4f, ", i ? "," : "",
                board.fingers[board.edges[i].finger].c_str(), e.time_s, e.angle_rad);
    PrintVector("point", e.point);
    std::printf(", ");
    PrintVector("normal_before", e.normal_before);
    std::printf(", ");
    PrintVector("normal_after", e.normal_after);
    std::printf("}");
  }
  std::printf("]}\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dmpl_surface: the object's surface as the supervisor learned it by touch in a "
               "recorded run, as JSON",
               "dmpl_surface"};
  std::string log_path;
  int directions = 400;
  app.add_option("LOG", log_path, "a run's log (run.lcmlog; full or analysis)")->required();
  app.add_option("--directions", directions, "directions the surface is given along")
      ->check(CLI::Range(1, 100000));
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  try {
    // The per-tick status where the log keeps it at every tick, else the 100 Hz report (an
    // analysis log keeps the status in bursts only: its gaps would break the edges' traces):
    // one of the two (the same contacts twice would weigh nothing more, but would cost), by the
    // rule the Python tools use (logdata.py). A first pass counts them.
    int statuses = 0, reports = 0;
    {
      dmpl::EventLogReader log(log_path);
      dmpl::LogEvent event;
      while (log.Next(&event)) {
        statuses += event.channel == dmpl::channels::kControllerStatus;
        reports += event.channel == dmpl::channels::kControllerReport;
      }
    }
    const std::string channel = statuses >= 5 * reports ? dmpl::channels::kControllerStatus
                                                        : dmpl::channels::kControllerReport;
    dmpl::EventLogReader log(log_path);
    dmpl::LogEvent event;
    std::unique_ptr<dmpl::Blackboard> board;
    int used = 0;
    while (log.Next(&event)) {
      dmpl::controller_status_t m;
      if (event.channel != channel ||
          !dmpl::DecodeMessage(event.data, static_cast<uint32_t>(event.size), &m)) {
        continue;
      }
      dmpl::LearnFromStatus(m, &board);
      ++used;
    }
    if (!board) throw std::runtime_error("no controller status in " + log_path);
    Print(*board, used, directions);
  } catch (const std::exception& e) {
    std::cerr << "dmpl_surface: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
