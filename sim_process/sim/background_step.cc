#include "sim_process/sim/background_step.h"

#include <sched.h>

#include <chrono>
#include <utility>

#include "components/runtime/check.h"

namespace dmpl {

namespace {
// How long either side spins before it sleeps: about a physics step.
constexpr auto kSpin = std::chrono::microseconds(50);

// Spins on `ready` for kSpin; true when it came.
template <typename Ready>
bool SpinFor(Ready ready) {
  const auto until = std::chrono::steady_clock::now() + kSpin;
  while (std::chrono::steady_clock::now() < until) {
    if (ready()) return true;
  }
  return ready();
}
}  // namespace

bool BackgroundStep::Parallel() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return false;
  return CPU_COUNT(&set) >= 2;
}

BackgroundStep::BackgroundStep() : thread_([this] { Run(); }) {}

BackgroundStep::~BackgroundStep() {
  try {
    Wait();
  } catch (...) {  // a step that failed while the node was being taken down: nothing to tell
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true, std::memory_order_release);
  }
  wake_.notify_one();
  thread_.join();
}

void BackgroundStep::Start(std::function<void()> job) {
  DMPL_DEMAND(!busy());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = std::move(job);
    busy_.store(true, std::memory_order_release);
  }
  wake_.notify_one();
}

void BackgroundStep::Wait() {
  if (!SpinFor([this] { return !busy(); })) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return !busy(); });
  }
  if (thrown_) std::rethrow_exception(std::exchange(thrown_, nullptr));
}

void BackgroundStep::Run() {
  for (;;) {
    const auto given = [this] { return busy() || stop_.load(std::memory_order_acquire); };
    if (!SpinFor(given)) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, given);
    }
    if (!busy()) return;  // the stop
    std::function<void()> job;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job = std::move(job_);
    }
    try {
      job();
    } catch (...) {
      thrown_ = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_.store(false, std::memory_order_release);
    }
    done_.notify_one();
  }
}

}  // namespace dmpl
