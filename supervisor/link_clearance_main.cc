// dmpl_link_clearance LOG --config CONFIG: how well the felt surface predicts a finger's links
// touching the object, over a recorded run, as JSON on stdout. Every `--every` ticks it takes
// each finger's links at the sensed joints (finger_links.h), their clearance from the surface
// the supervisor had felt so far (its own Blackboard::LearnSurface, as dmpl_surface) at the
// controller's object estimate (link_clearance.h), and sets it beside the simulator's truth of
// whether a link pushed on the object (fingertip_contact_t.link_force_n). Needs a full log (the
// truth channel). At each onset of a link's touch, how long the prediction had been within 2 mm
// (a warning a placement could act on). Exit 2 with one message on a log or config it cannot
// read.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "components/hand/hand_model.h"
#include "components/kinematics/finger_links.h"
#include "components/logging/decode.h"
#include "components/logging/event_log_reader.h"
#include "components/runtime/channels.h"
#include "components/runtime/command_line.h"
#include "components/runtime/config.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "supervisor/blackboard.h"
#include "supervisor/link_clearance.h"
#include "supervisor/supervisor_translation.h"

namespace {

// The predicted clearance's bins (m), and a last one for "no verdict".
constexpr double kBins[] = {0.0, 0.002, 0.005};
constexpr int kNumBins = 5;  // < 0, < 2 mm, < 5 mm, >= 5 mm, unknown
constexpr double kTouchN = 0.05;  // a link pushing more than this touches (the truth)
constexpr double kWarnM = 0.002;  // a prediction this near warns of a touch

int Bin(const std::optional<double>& clearance) {
  if (!clearance) return kNumBins - 1;
  int b = 0;
  while (b < 3 && *clearance >= kBins[b]) ++b;
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dmpl_link_clearance: the felt surface's prediction of link contacts against the "
               "simulator's truth over a recorded run, as JSON",
               "dmpl_link_clearance"};
  std::string log_path, config_path;
  int every = 10;
  app.add_option("LOG", log_path, "a run's full log (run.lcmlog)")->required();
  app.add_option("--config", config_path, "the run's config (its hand section)")
      ->required()
      ->type_name("FILE");
  app.add_option("--every", every, "ticks between two samples")->check(CLI::Range(1, 100000));
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  try {
    const dmpl::Config config = dmpl::Config::Resolve(config_path, {}, {});
    dmpl::HandParams hand_params;
    config.Load("hand", &hand_params);
    const dmpl::HandModel model = dmpl::HandModel::Load(hand_params);
    const dmpl::HandKinematics kin(model);
    std::vector<dmpl::FingerLinks> links;
    for (int f = 0; f < kin.num_fingers(); ++f) links.emplace_back(model, kin.finger(f));

    dmpl::EventLogReader log(log_path);
    dmpl::LogEvent event;
    std::unique_ptr<dmpl::Blackboard> board;
    std::vector<double> joints;
    // counts[touching][bin]
    long counts[2][kNumBins] = {};
    long truths = 0;
    // Per finger: whether a link touched at the last sample, and since when the prediction has
    // been within kWarnM (-1: it is not). At each touch's onset, how long it had warned.
    std::vector<bool> touched(kin.num_fingers(), false);
    std::vector<double> warned_since(kin.num_fingers(), -1.0);
    std::vector<double> leads;
    int onsets = 0;
    while (log.Next(&event)) {
      const auto size = static_cast<uint32_t>(event.size);
      if (event.channel == dmpl::channels::kControllerStatus) {
        dmpl::controller_status_t m;
        if (dmpl::DecodeMessage(event.data, size, &m)) dmpl::LearnFromStatus(m, &board);
      } else if (event.channel == dmpl::channels::kSensors) {
        dmpl::hand_sensors_t m;
        if (dmpl::DecodeMessage(event.data, size, &m)) joints = m.joints.position;
      } else if (event.channel == dmpl::channels::kSensorsTrue) {
        dmpl::hand_sensors_t m;
        if (!dmpl::DecodeMessage(event.data, size, &m) || ++truths % every != 0) continue;
        if (!board || static_cast<int>(joints.size()) != kin.num_joints()) continue;
        for (const auto& tip : m.tactile.fingers) {
          const int f = kin.FindFinger(tip.finger);
          if (f < 0) continue;
          std::optional<double> least;
          for (const dmpl::LinkSolid& c : links[f].Solids(kin.FingerJoints(f, joints))) {
            if (c.tip) continue;
            const auto gap = dmpl::SurfaceClearance(c, board->surface, board->view.object);
            if (gap) least = least ? std::min(*least, *gap) : *gap;
          }
          const bool touching = tip.link_force_n > kTouchN;
          ++counts[touching][Bin(least)];
          const double now = m.utime * 1e-6;
          const bool warns = least && *least < kWarnM;
          if (!warns) warned_since[f] = -1.0;
          if (warns && warned_since[f] < 0) warned_since[f] = now;
          if (touching && !touched[f]) {
            ++onsets;
            if (warns) leads.push_back(now - warned_since[f]);
          }
          touched[f] = touching;
        }
      }
    }
    if (!board || truths == 0) {
      throw std::runtime_error(log_path + " has no controller status or no simulator truth "
                               "(a full log is needed)");
    }
    const char* names[kNumBins] = {"inside", "under_2mm", "under_5mm", "clear", "unknown"};
    std::printf("{\"samples_every_ticks\": %d", every);
    for (int touching = 1; touching >= 0; --touching) {
      std::printf(", \"%s\": {", touching ? "link_touching" : "no_link_touch");
      for (int b = 0; b < kNumBins; ++b) {
        std::printf("%s\"%s\": %ld", b ? ", " : "", names[b], counts[touching][b]);
      }
      std::printf("}");
    }
    std::sort(leads.begin(), leads.end());
    const double median = leads.empty() ? 0.0 : leads[leads.size() / 2];
    std::printf(", \"touch_onsets\": %d, \"onsets_warned\": %zu, \"warning_lead_median_s\": %.3f",
                onsets, leads.size(), median);
    std::printf("}\n");
  } catch (const std::exception& e) {
    std::cerr << "dmpl_link_clearance: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
