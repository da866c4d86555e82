#pragma once
// Lockstep join (DESIGN.md §1): a node's tick k runs once every input it needs for tick k has
// arrived. Input i for tick k is the message with seq == k + offset_i (offset -1 for an answer
// to the previous tick, such as the supervisor's task command). Each tick fires exactly once;
// messages for ticks already done are stale and counted.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dmpl {

class LockstepGate {
 public:
  struct Input {
    std::string name;
    int64_t seq_offset = 0;   // the message for tick k carries seq k + seq_offset
    int64_t first_tick = 0;   // ticks before this do not wait for the input
  };

  explicit LockstepGate(std::vector<Input> inputs);

  // Records that input `index` arrived with `seq`. Returns the tick that became complete, if any.
  std::optional<int64_t> Arrive(size_t index, int64_t seq);

  // The last tick that fired (-1 before the first).
  int64_t last_tick() const { return last_tick_; }
  int64_t stale_count() const { return stale_; }
  // Names of inputs still missing for the next tick (for fault messages).
  std::string Missing() const;

 private:
  bool Complete(int64_t tick) const;

  std::vector<Input> inputs_;
  std::vector<int64_t> latest_;   // latest tick each input has delivered (-inf: none)
  int64_t last_tick_ = -1;
  int64_t stale_ = 0;
};

}  // namespace dmpl
