#pragma once
// One job at a time on a thread of its own: the simulator's physics step, run while the nodes of
// the same process answer the tick before (one process, lockstep, an actuation delay of a tick:
// the step from k to k + 1 applies the command of k - 1, which is in before tick k goes out, so
// the step and the answer to tick k need nothing of each other). The caller waits for the job
// before it touches what the job touches. Hand-over by spinning briefly, then sleeping: a tick
// is tens of microseconds, a condition variable's wake-up alone several.
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace dmpl {

class BackgroundStep {
 public:
  BackgroundStep();
  ~BackgroundStep();
  BackgroundStep(const BackgroundStep&) = delete;
  BackgroundStep& operator=(const BackgroundStep&) = delete;

  // Runs `job` on the thread; the previous job must have been waited for.
  void Start(std::function<void()> job);
  // Until the job started last has finished (at once when none is under way); what it threw is
  // thrown here, on the caller's thread.
  void Wait();
  bool busy() const { return busy_.load(std::memory_order_acquire); }
  // Whether this process may run on two CPUs or more (its affinity): on one, a second thread
  // only takes turns with the first.
  static bool Parallel();

 private:
  void Run();

  std::function<void()> job_;
  std::exception_ptr thrown_;
  std::atomic<bool> busy_{false};  // a job is given and not yet done
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;  // the thread, for a job or the stop
  std::condition_variable done_;  // the caller, for the job's end
  std::thread thread_;
};

}  // namespace dmpl
