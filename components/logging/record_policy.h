#pragma once
// Record policies: what a run's log keeps of each channel (run.record, --record).
//   full      every message of every channel: what replaying a run to reproduce it needs.
//   analysis  what metrics, the report, calibration and a viewer read, at the rates they read it:
//             the truth at 100 Hz and at every tick where a fingertip touches, lets go or its
//             force jumps (contact events are faster than 100 Hz); the sensed channel at 50 Hz;
//             the controller's 100 Hz report (with every event) and its per-tick status in
//             bursts of 100 consecutive ticks every 1000 (the calibration's force-response
//             windows); tasks when they change; status and management channels whole; not the
//             targets, joint commands or IK status.
//   none      no log (the recorder still extracts the metrics' columns online).
// The one table of these rules is in record_policy.cc.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace dmpl {

enum class RecordPolicy { kFull, kAnalysis, kNone };

// Parses "full", "analysis" or "none"; throws std::invalid_argument naming the choices.
RecordPolicy ParseRecordPolicy(const std::string& name);
const char* RecordPolicyName(RecordPolicy policy);

// How a policy keeps one channel.
struct KeepRule {
  enum Kind { kAll, kEveryTicks, kOnChange, kBursts, kNever, kEveryTicksOrTouch };
  Kind kind = kAll;
  int64_t period = 1;  // kEveryTicks(OrTouch): seq % period == 0; kBursts: seq % period < length
  int64_t length = 0;
  double force_jump_n = 0.0;  // kEveryTicksOrTouch: a fingertip force this far from the last kept
};

// The rule of `channel` under `policy` (kAll for channels the table does not name).
KeepRule RuleFor(RecordPolicy policy, const std::string& channel);

// Decides message by message what a log keeps. dmpl messages begin with their fingerprint,
// utime and seq (8 bytes each, big-endian), so the tick is read from the bytes; a message too
// short to carry one is kept (it is something the tools should see, not a tick to thin out).
class RecordFilter {
 public:
  explicit RecordFilter(RecordPolicy policy) : policy_(policy) {}
  bool Keep(const std::string& channel, const void* data, size_t size);
  RecordPolicy policy() const { return policy_; }

 private:
  bool TouchChanged(const std::string& channel, const KeepRule& rule, const void* data,
                    size_t size);

  RecordPolicy policy_;
  std::map<std::string, KeepRule> rules_;                  // cache by channel
  std::map<std::string, std::vector<uint8_t>> last_kept_;  // kOnChange: the last kept payload
  std::map<std::string, std::vector<double>> last_touch_;  // kEveryTicksOrTouch: per finger,
                                                           // force (or -1: no contact)
};

}  // namespace dmpl
