#pragma once
// Lockstep join (README, "Lockstep and real time"): a node's tick k runs once every input it
// needs for tick k has arrived. Input 0 drives: one message per tick, its seq is the tick.
// Every other input i serves tick k with the message of seq k + offset_i, rounded down to a
// multiple of period_i (offset -1 for an answer to the previous tick, such as the supervisor's
// task command; period 10 when the supervisor answers every tenth tick). Ticks fire in order,
// each exactly once (a tick whose driving message was lost is skipped: the simulator reports the
// missing answer); messages for ticks already done are stale and counted.
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace dmpl {

class LockstepGate {
 public:
  struct Input {
    std::string name;
    int64_t seq_offset = 0;   // the message for tick k carries seq k + seq_offset ...
    int64_t first_tick = 0;   // ticks before this do not wait for the input
    int64_t period = 1;       // ... rounded down to a multiple of period (inputs other than 0)
  };

  explicit LockstepGate(std::vector<Input> inputs);

  // Records that input `index` arrived with `seq`. Returns the ticks that became complete, in
  // order (often none or one; an answer that serves several ticks can complete more).
  std::vector<int64_t> Arrive(size_t index, int64_t seq);

  // The last tick that fired (-1 before the first).
  int64_t last_tick() const { return last_tick_; }
  int64_t stale_count() const { return stale_; }
  // Names of inputs still missing for the next tick (for fault messages).
  std::string Missing() const;

 private:
  bool Complete(int64_t tick) const;
  // The last tick the message of input `index` with `seq` serves.
  int64_t LastTickServed(size_t index, int64_t seq) const;

  std::vector<Input> inputs_;
  std::vector<int64_t> served_;   // per input: the last tick it serves (-inf: none)
  std::set<int64_t> pending_;     // ticks input 0 delivered that have not fired
  int64_t last_tick_ = -1;
  int64_t stale_ = 0;
};

}  // namespace dmpl
