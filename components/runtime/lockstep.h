#pragma once
// Lockstep join (README, "Lockstep and real time"): a node's tick k runs once every input it
// needs for tick k has arrived. Input 0 drives: one message per tick, its seq is the tick.
// Every other input i serves tick k with the message of seq k + offset_i, rounded down to a
// multiple of period_i (offset -1 for an answer to the previous tick, such as the supervisor's
// task command; period 10 when the supervisor answers every tenth tick). Ticks fire in order,
// each exactly once (a tick whose driving message was lost is skipped: the simulator reports the
// missing answer); messages for ticks already done are stale and counted.
#include <cstdint>
#include <map>
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

  // consecutive: tick k + 1 never fires before tick k (a lost message is sent again, see
  // resend.h, and the ticks after it wait for it); otherwise a tick whose driving message was
  // lost is skipped.
  explicit LockstepGate(std::vector<Input> inputs, bool consecutive = false);

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
  bool consecutive_;
  std::vector<int64_t> served_;   // per input: the last tick it serves (-inf: none)
  std::set<int64_t> pending_;     // ticks input 0 delivered that have not fired
  int64_t last_tick_ = -1;
  int64_t stale_ = 0;
};

// How far past the loop's tick a seq may be and still be adopted; beyond, it is forged or
// another run's, and adopting it would push the real ticks out of a node's queues.
inline constexpr int64_t kMaxTicksAhead = 1000;

// One stream delivered in seq order, for a node whose computation has state (lockstep): a
// message ahead of the next one waits until the ones before it arrive (sent again after a loss);
// copies of delivered messages are dropped. The stream starts at the first seq seen; a seq more
// than `max_ahead` past the next is refused (kMaxTicksAhead).
template <typename T>
class InOrder {
 public:
  explicit InOrder(int64_t max_ahead = kMaxTicksAhead) : max_ahead_(max_ahead) {}

  enum class Verdict { kAccepted, kDuplicate, kTooFarAhead };
  // Records `item`; the items now deliverable, oldest first, go to `ready`.
  Verdict Arrive(int64_t seq, T item, std::vector<T>* ready) {
    ready->clear();
    if (seq < 0 || (started_ && seq < next_)) return Verdict::kDuplicate;  // ticks count from 0
    if (started_ && seq - next_ > max_ahead_) return Verdict::kTooFarAhead;
    if (!started_) {
      started_ = true;
      next_ = seq;
    }
    waiting_.emplace(seq, std::move(item));  // a copy of a waiting one changes nothing
    while (!waiting_.empty() && waiting_.begin()->first == next_) {
      ready->push_back(std::move(waiting_.begin()->second));
      waiting_.erase(waiting_.begin());
      ++next_;
    }
    return Verdict::kAccepted;
  }
  size_t waiting() const { return waiting_.size(); }
  int64_t next() const { return next_; }

 private:
  int64_t max_ahead_;
  bool started_ = false;
  int64_t next_ = 0;
  std::map<int64_t, T> waiting_;
};

}  // namespace dmpl
