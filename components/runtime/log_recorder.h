#pragma once
// Records every message of an LCM instance into an LCM log file (the format of lcm-logger and
// lcm.EventLog). Its subscription queue is large: at 1 kHz lockstep a short stall of the recorder
// must not drop messages (LCM's default queue holds 30).
#include <lcm/eventlog.h>

#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "components/runtime/lcm_bus.h"

namespace dmpl {

class LogRecorder {
 public:
  // Records every bus of `bus`. Throws std::runtime_error when the file cannot be created.
  LogRecorder(LcmBus* bus, const std::string& path, const std::string& channels = ".*");
  ~LogRecorder();
  LogRecorder(const LogRecorder&) = delete;
  LogRecorder& operator=(const LogRecorder&) = delete;

  void Flush();
  int64_t written() const { return written_; }
  int64_t failed() const { return failed_; }

 private:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  lcm_eventlog_t* log_;
  std::vector<std::pair<lcm::LCM*, lcm::Subscription*>> subs_;
  int64_t written_ = 0;
  int64_t failed_ = 0;
};

}  // namespace dmpl
