#pragma once
// A process's configuration: one YAML document (usually an experiment file) with one top-level
// section per component, plus command-line overrides. Each component reads its own section into
// its parameter struct; the `run` section is shared by all.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "components/runtime/params.h"

namespace dmpl {

// Settings every process shares (section `run`).
struct RunParams {
  std::string lcm_url;             // empty: --lcm-url, else $LCM_DEFAULT_URL, else the default
  int64_t seed = 1;                // noise and anything random derive from (seed, seq)
  bool lockstep = true;            // false: real time
  bool channel_buses = true;       // udpm: each group of channels on its own port (channels.h)
  double tick_timeout_s = 2.0;     // lockstep: a missing answer after this long is a fault
  int max_tick_faults = 5;         // lockstep: give up (exit non-zero) after this many faults
  double resend_after_s = 0.005;   // lockstep: a node sends its last messages again when the
                                   // loop has stalled this long (a lost message; 0: never)
  double heartbeat_period_s = 0.25;
  std::vector<std::string> lockstep_participants = {"dmpl_noise", "dmpl_ik", "dmpl_controller"};
  std::string record = "full";     // what the run's log keeps: full, analysis or none (tools)
  double tick_s = 0.001;           // the loop's period, one simulator tick: the controller's
                                   // control period (the simulator checks it against its step)
  double view_rate_hz = 30.0;      // DMPL_VIEW_TRUTH / _SENSED for viewers (sim time); 0: none
  bool respawn = false;            // the launcher restarts a process that dies (tools)
  int64_t run_id = 0;              // this run's identity (tools/dmpl run draws one): messages
                                   // of another run are ignored; 0: none (accepts every run's)
  bool record_receipts = true;      // a network bus: each node keeps what it publishes until
                                   // the recorder confirms it (record_confirm.h)
  std::string journal_dir;         // non-empty: a node that holds the run's state (the
                                   // supervisor) journals its inputs there, and a restarted one
                                   // takes up from them (tools/dmpl run --respawn sets it)

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(lcm_url));
    a->Visit(DMPL_NVP(seed));
    a->Visit(DMPL_NVP(lockstep));
    a->Visit(DMPL_NVP(channel_buses));
    a->Visit(DMPL_NVP(tick_timeout_s), Above(0));
    a->Visit(DMPL_NVP(max_tick_faults), AtLeast(1));
    a->Visit(DMPL_NVP(resend_after_s), AtLeast(0));
    a->Visit(DMPL_NVP(heartbeat_period_s), Above(0));
    a->Visit(DMPL_NVP(lockstep_participants));
    a->Visit(DMPL_NVP(record));
    a->Visit(DMPL_NVP(tick_s), AboveUpTo(0, 0.1));
    a->Visit(DMPL_NVP(view_rate_hz), AtLeast(0));
    a->Visit(DMPL_NVP(respawn));
    a->Visit(DMPL_NVP(run_id));
    a->Visit(DMPL_NVP(record_receipts));
    a->Visit(DMPL_NVP(journal_dir));
  }
  void Validate(const std::string& source) const { CheckBounds(*this, source, "run"); }
};

// Decimates a stream by its sim time: true once per 1 / rate_hz of it (never for rate_hz <= 0).
class RateGate {
 public:
  explicit RateGate(double rate_hz)
      : period_us_(rate_hz > 0 ? static_cast<int64_t>(1e6 / rate_hz) : 0) {}
  bool Due(int64_t utime) {
    if (period_us_ <= 0 || utime < next_us_) return false;
    next_us_ = utime - utime % period_us_ + period_us_;
    return true;
  }

 private:
  int64_t period_us_;
  int64_t next_us_ = 0;
};

inline constexpr char kDefaultLcmUrl[] = "udpm://239.255.76.67:7667?ttl=0";

// The top-level sections a config may have. Anything else is a typo and an error.
const std::vector<std::string>& KnownConfigSections();

// The resolved configuration of one process.
class Config {
 public:
  Config() : root_(YAML::NodeType::Map) {}

  // Builds from a file (may be empty: all defaults), --params overlays and --set overrides.
  static Config Resolve(const std::string& file, const std::vector<std::string>& params_files,
                        const std::vector<std::string>& set_overrides);

  // Reads section `name` into `out` (a missing section keeps the defaults).
  template <typename T>
  void Load(const std::string& name, T* out) const {
    const YAML::Node& root = root_;
    YAML::Node section = root[name];
    if (!section.IsDefined() || section.IsNull()) return;
    YamlReadArchive::Load(section, source_, name, out);
  }

  const YAML::Node& root() const { return root_; }
  // A copy without one top-level section (the object, for every node but the simulator).
  Config Without(const std::string& section) const;
  const std::string& source() const { return source_; }

 private:
  YAML::Node root_;
  std::string source_ = "(defaults)";
};

// The LCM URL: --lcm-url, else run.lcm_url, else $LCM_DEFAULT_URL, else kDefaultLcmUrl.
std::string ResolveLcmUrl(const std::string& cli_url, const RunParams& run);

}  // namespace dmpl
