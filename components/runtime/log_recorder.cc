#include "components/runtime/log_recorder.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "components/logging/message_layout.h"
#include "components/runtime/channels.h"

namespace dmpl {

namespace {

// A message that is not this run's (the nodes' rule: channels::OfRun).
bool OfAnotherRun(const std::string& channel, const uint8_t* data, size_t size, int64_t run_id) {
  return !channels::OfRun(run_id, RunIdOf(data, size), channels::IsLoopChannel(channel));
}

}  // namespace

LogRecorder::LogRecorder(LcmBus* bus, const RecordOptions& options)
    : filter_(options.policy), run_id_(options.run_id) {
  if (options.policy != RecordPolicy::kNone) {
    if (options.log_path.empty()) throw std::runtime_error("no log file to record to");
    log_ = lcm_eventlog_create(options.log_path.c_str(), "w");
    if (log_ == nullptr) {
      throw std::runtime_error("cannot create log file '" + options.log_path +
                               "': " + std::strerror(errno));
    }
  }
  if (!options.columns_dir.empty()) {
    columns_ = std::make_unique<LogColumns>(options.columns_dir, ".*", options.columns_fields);
  }
  for (lcm::LCM* l : bus->All()) {
    lcm::Subscription* sub = l->subscribe(options.channels, &LogRecorder::OnMessage, this);
    sub->setQueueCapacity(1 << 20);
    subs_.emplace_back(l, sub);
  }
}

LogRecorder::~LogRecorder() {
  for (auto& [l, sub] : subs_) l->unsubscribe(sub);
  if (log_ != nullptr) lcm_eventlog_destroy(log_);
}

void LogRecorder::Flush() {
  if (log_ != nullptr) fflush(log_->f);
}

void LogRecorder::Finish() {
  Flush();
  if (columns_) {
    columns_->Finish("\"recorded\": {\"policy\": \"" +
                     std::string(RecordPolicyName(filter_.policy())) + "\", \"received\": " +
                     std::to_string(received_) + ", \"written\": " + std::to_string(written_) +
                     ", \"failed\": " + std::to_string(failed_) +
                     ", \"copies\": " + std::to_string(copies_) + "}");
  }
}

bool LogRecorder::IsCopy(const std::string& channel, const uint8_t* data, size_t size) {
  // A resent message is one of a node's last 8, sent again within about a second (resend.h);
  // the window is wide enough that other traffic on the channel (garbage, a forger's) cannot
  // push the original out of it first.
  constexpr size_t kRemembered = 512;
  uint64_t hash = 14695981039346656037ull;  // FNV-1a
  for (size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 1099511628211ull;
  RecentHashes& recent = recent_[channel];
  if (recent.set.count(hash) != 0) return true;
  recent.order.push_back(hash);
  recent.set.insert(hash);
  if (recent.order.size() > kRemembered) {
    recent.set.erase(recent.order.front());
    recent.order.pop_front();
  }
  return false;
}

void LogRecorder::OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  const auto* data = static_cast<const uint8_t*>(rbuf->data);
  if (OfAnotherRun(channel, data, rbuf->data_size, run_id_)) {
    ++foreign_;
    return;
  }
  if (IsCopy(channel, data, rbuf->data_size)) {
    ++copies_;
    return;
  }
  ++received_;
  if (columns_) columns_->Add(channel, data, rbuf->data_size);
  if (log_ == nullptr || !filter_.Keep(channel, data, rbuf->data_size)) return;
  lcm_eventlog_event_t event{};
  event.eventnum = written_;
  event.timestamp = rbuf->recv_utime;
  event.channellen = static_cast<int32_t>(channel.size());
  event.datalen = static_cast<int32_t>(rbuf->data_size);
  event.channel = const_cast<char*>(channel.c_str());
  event.data = rbuf->data;
  if (lcm_eventlog_write_event(log_, &event) != 0) {
    ++failed_;
    return;
  }
  ++written_;
}

}  // namespace dmpl
