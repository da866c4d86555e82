#include "components/runtime/lockstep.h"

#include <limits>

#include "components/runtime/check.h"

namespace dmpl {

LockstepGate::LockstepGate(std::vector<Input> inputs)
    : inputs_(std::move(inputs)),
      latest_(inputs_.size(), std::numeric_limits<int64_t>::min()) {
  DMPL_DEMAND(!inputs_.empty());
}

bool LockstepGate::Complete(int64_t tick) const {
  for (size_t i = 0; i < inputs_.size(); ++i) {
    if (tick < inputs_[i].first_tick) continue;
    if (latest_[i] < tick) return false;
  }
  return true;
}

std::optional<int64_t> LockstepGate::Arrive(size_t index, int64_t seq) {
  DMPL_DEMAND(index < inputs_.size());
  const int64_t tick = seq - inputs_[index].seq_offset;
  if (tick <= last_tick_) {
    ++stale_;
    return std::nullopt;
  }
  if (tick > latest_[index]) latest_[index] = tick;
  // Ticks are sequential in lockstep: the arriving message can only complete its own tick.
  if (!Complete(tick)) return std::nullopt;
  last_tick_ = tick;
  return tick;
}

std::string LockstepGate::Missing() const {
  std::string missing;
  const int64_t next = last_tick_ + 1;
  for (size_t i = 0; i < inputs_.size(); ++i) {
    if (next >= inputs_[i].first_tick && latest_[i] < next) {
      missing += (missing.empty() ? "" : ", ") + inputs_[i].name;
    }
  }
  return missing;
}

}  // namespace dmpl
