#pragma once
#include <chrono>
#include <cstdint>

namespace dmpl {

// Wall-clock microseconds since the epoch (heartbeats, process status).
inline int64_t WallMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Monotonic seconds, for measuring durations and scheduling timers.
inline double MonotonicSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace dmpl
