#include "components/runtime/lockstep.h"

#include <limits>

#include "components/runtime/check.h"

namespace dmpl {

LockstepGate::LockstepGate(std::vector<Input> inputs, bool consecutive)
    : inputs_(std::move(inputs)),
      consecutive_(consecutive),
      served_(inputs_.size(), std::numeric_limits<int64_t>::min()) {
  DMPL_DEMAND(!inputs_.empty());
  DMPL_DEMAND(inputs_[0].seq_offset == 0 && inputs_[0].period == 1);
  for (const Input& in : inputs_) DMPL_DEMAND(in.period >= 1);
}

int64_t LockstepGate::LastTickServed(size_t index, int64_t seq) const {
  // seq serves every tick k with floor((k + offset) / period) * period == seq.
  const Input& in = inputs_[index];
  return seq - in.seq_offset + in.period - 1;
}

bool LockstepGate::Complete(int64_t tick) const {
  for (size_t i = 1; i < inputs_.size(); ++i) {
    if (tick < inputs_[i].first_tick) continue;
    if (served_[i] < tick) return false;
  }
  return true;
}

std::vector<int64_t> LockstepGate::Arrive(size_t index, int64_t seq) {
  DMPL_DEMAND(index < inputs_.size());
  const int64_t served = LastTickServed(index, seq);
  if (served <= last_tick_ || (index == 0 && pending_.count(seq) != 0)) {
    ++stale_;
    return {};
  }
  if (index == 0) {
    pending_.insert(seq);
  } else if (served > served_[index]) {
    served_[index] = served;
  }
  std::vector<int64_t> fired;
  auto next_in_turn = [this] {
    return !consecutive_ || last_tick_ < 0 || *pending_.begin() == last_tick_ + 1;
  };
  while (!pending_.empty() && next_in_turn() && Complete(*pending_.begin())) {
    last_tick_ = *pending_.begin();
    pending_.erase(pending_.begin());
    fired.push_back(last_tick_);
  }
  return fired;
}

std::string LockstepGate::Missing() const {
  const int64_t next = pending_.empty() || (consecutive_ && last_tick_ >= 0)
                           ? last_tick_ + 1
                           : *pending_.begin();
  std::string missing = pending_.count(next) == 0 ? inputs_[0].name : "";
  for (size_t i = 1; i < inputs_.size(); ++i) {
    if (next >= inputs_[i].first_tick && served_[i] < next) {
      missing += (missing.empty() ? "" : ", ") + inputs_[i].name;
    }
  }
  return missing;
}

}  // namespace dmpl
