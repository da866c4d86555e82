#pragma once
// Records the messages of an LCM instance into an LCM log file (the format of lcm-logger and
// lcm.EventLog), keeping what its record policy keeps, and (when asked) extracts every message's
// columns for the metrics online, whatever the policy keeps. Its subscription queue is large: at
// 1 kHz lockstep a short stall of the recorder must not drop messages (LCM's default holds 30).
#include <lcm/eventlog.h>

#include <cstdint>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "components/logging/log_columns.h"
#include "components/logging/record_policy.h"
#include "components/runtime/lcm_bus.h"
#include "components/runtime/record_confirm.h"
#include "dmpl/record_ledger_t.hpp"

namespace dmpl {

struct RecordOptions {
  std::string log_path;  // empty: no log (policy none)
  RecordPolicy policy = RecordPolicy::kFull;
  std::string channels = ".*";
  std::string columns_dir;            // non-empty: the metrics' columns of every message, online
  std::string columns_fields = ".*";  // which of their fields (LogColumns)
  int64_t run_id = 0;                 // non-zero: messages of another run are not recorded
};

class LogRecorder {
 public:
  // Records every bus of `bus`. Throws std::runtime_error when a file cannot be created.
  LogRecorder(LcmBus* bus, const RecordOptions& options);
  ~LogRecorder();
  LogRecorder(const LogRecorder&) = delete;
  LogRecorder& operator=(const LogRecorder&) = delete;

  void Flush();
  // Closes the columns (writes their meta.json). Throws std::runtime_error on I/O errors.
  void Finish();
  int64_t received() const { return received_; }
  int64_t written() const { return written_; }
  int64_t failed() const { return failed_; }
  int64_t copies() const { return copies_; }
  int64_t foreign() const { return foreign_; }
  // Messages asked for again (receipts that were not complete).
  int64_t asked_again() const { return asked_again_; }

 private:
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  // A publisher's ledger: a receipt per channel (record_confirm.h).
  void OnLedger(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  // True when the message's bytes are those of one of the last on its channel (messages
  // without a seq): a copy sent again after a loss (resend.h), which the log keeps once.
  bool IsCopy(const std::string& channel, uint64_t hash);
  // Whether the messages a ledger entry lists and the recorder lacks are lost, not just still
  // on their way.
  bool SureItIsLost(const std::string& publisher, const LedgerEntry& entry, bool stopping);
  struct RecentHashes {
    std::deque<uint64_t> order;
    std::unordered_set<uint64_t> set;
  };
  std::unordered_map<std::string, RecentHashes> recent_;  // per channel
  lcm_eventlog_t* log_ = nullptr;
  RecordFilter filter_;
  std::unique_ptr<LogColumns> columns_;
  std::vector<int> subscriptions_;  // ids on bus_
  LcmBus* bus_;
  ReceivedRecord received_record_;
  std::unordered_map<std::string, LedgerEntry> final_ledgers_;  // publisher/channel: the last
  int64_t asked_again_ = 0;
  int64_t received_ = 0;
  int64_t written_ = 0;
  int64_t failed_ = 0;
  int64_t copies_ = 0;
  int64_t foreign_ = 0;
  int64_t run_id_ = 0;
};

}  // namespace dmpl
