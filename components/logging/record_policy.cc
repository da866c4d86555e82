#include "components/logging/record_policy.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "components/logging/decode.h"
#include "components/logging/message_layout.h"
#include "components/runtime/channels.h"
#include "dmpl/hand_sensors_t.hpp"

namespace dmpl {
namespace {

// The analysis policy, channel by channel (see record_policy.h for why each rate).
KeepRule AnalysisRule(const std::string& channel) {
  using K = KeepRule;
  if (channel == channels::kSensorsTrue) return {K::kEveryTicksOrTouch, 10, 0, 0.25};
  if (channel == channels::kSensors) return {K::kEveryTicks, 20};
  if (channel == channels::kControllerStatus) return {K::kBursts, 1000, 100};
  if (channel == channels::kTask) return {K::kOnChange};
  if (channel == channels::kFingerTargets || channel == channels::kJointCmd ||
      channel == channels::kIkStatus) {
    return {K::kNever};
  }
  return {K::kAll};
}

}  // namespace

RecordPolicy ParseRecordPolicy(const std::string& name) {
  if (name == "full") return RecordPolicy::kFull;
  if (name == "analysis") return RecordPolicy::kAnalysis;
  if (name == "none") return RecordPolicy::kNone;
  throw std::invalid_argument("unknown record policy '" + name +
                              "' (expected full, analysis or none)");
}

const char* RecordPolicyName(RecordPolicy policy) {
  switch (policy) {
    case RecordPolicy::kFull:
      return "full";
    case RecordPolicy::kAnalysis:
      return "analysis";
    case RecordPolicy::kNone:
      return "none";
  }
  return "?";
}

KeepRule RuleFor(RecordPolicy policy, const std::string& channel) {
  switch (policy) {
    case RecordPolicy::kFull:
      return {KeepRule::kAll};
    case RecordPolicy::kAnalysis:
      return AnalysisRule(channel);
    case RecordPolicy::kNone:
      return {KeepRule::kNever};
  }
  return {KeepRule::kAll};
}

bool RecordFilter::Keep(const std::string& channel, const void* data, size_t size) {
  auto it = rules_.find(channel);
  if (it == rules_.end()) it = rules_.emplace(channel, RuleFor(policy_, channel)).first;
  const KeepRule& rule = it->second;
  switch (rule.kind) {
    case KeepRule::kAll:
      return true;
    case KeepRule::kNever:
      return false;
    case KeepRule::kEveryTicksOrTouch: {
      const int64_t seq = SeqOf(data, size);
      const bool changed = TouchChanged(channel, rule, data, size);  // always tracks the touch
      return seq < 0 || seq % rule.period == 0 || changed;
    }
    case KeepRule::kEveryTicks:
    case KeepRule::kBursts: {
      const int64_t seq = SeqOf(data, size);
      if (seq < 0) return true;
      const int64_t phase = seq % rule.period;
      return rule.kind == KeepRule::kEveryTicks ? phase == 0 : phase < rule.length;
    }
    case KeepRule::kOnChange: {
      // The content after the header (fingerprint, run, utime, seq): a task re-sent unchanged
      // is not kept.
      const auto* bytes = static_cast<const uint8_t*>(data);
      const size_t skip = HeaderSize(data, size);
      auto [last, first] = last_kept_.try_emplace(channel);
      std::vector<uint8_t>& kept = last->second;
      if (!first && kept.size() == size - skip &&
          std::memcmp(kept.data(), bytes + skip, size - skip) == 0) {
        return false;
      }
      kept.assign(bytes + skip, bytes + size);
      return true;
    }
  }
  return true;
}

// True when a fingertip touched, let go, or its force moved by force_jump_n since the last kept
// message of the channel; remembers the touch of every message it keeps.
bool RecordFilter::TouchChanged(const std::string& channel, const KeepRule& rule, const void* data,
                                size_t size) {
  hand_sensors_t m;
  if (!DecodeMessage(data, static_cast<uint32_t>(size), &m)) return true;  // keep what tools cannot read
  std::vector<double> touch;
  for (const auto& f : m.tactile.fingers) touch.push_back(f.in_contact ? f.force_n : -1.0);
  std::vector<double>& last = last_touch_[channel];
  bool changed = last.size() != touch.size();
  for (size_t i = 0; !changed && i < touch.size(); ++i) {
    changed = (touch[i] < 0) != (last[i] < 0) || std::abs(touch[i] - last[i]) > rule.force_jump_n;
  }
  const bool due = SeqOf(data, size) % rule.period == 0;
  if (changed || due) last = touch;
  return changed;
}

}  // namespace dmpl
