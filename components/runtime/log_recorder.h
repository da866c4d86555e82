#pragma once
// Records every message of an LCM instance into an LCM log file (the format of lcm-logger and
// lcm.EventLog). Its subscription queue is large: at 1 kHz lockstep a short stall of the recorder
// must not drop messages (LCM's default queue holds 30).
#include <lcm/eventlog.h>

#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>

namespace dmpl {

class LogRecorder {
 public:
  // Throws std::runtime_error when the file cannot be created.
  LogRecorder(lcm::LCM* lcm, const std::string& path, const std::string& channels = ".*");
  ~LogRecorder();
  LogRecorder(const LogRecorder&) = delete;
  LogRecorder& operator=(const LogRecorder&) = delete;

  void Flush();
  int64_t written() const { return written_; }
  int64_t failed() const { return failed_; }

 private:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  lcm::LCM* lcm_;
  lcm_eventlog_t* log_;
  lcm::Subscription* sub_;
  int64_t written_ = 0;
  int64_t failed_ = 0;
};

}  // namespace dmpl
