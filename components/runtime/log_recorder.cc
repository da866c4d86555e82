#include "components/runtime/log_recorder.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "components/logging/decode.h"
#include "components/logging/message_layout.h"
#include "components/runtime/channels.h"
#include "components/runtime/clock.h"
#include "dmpl/record_receipt_t.hpp"

namespace dmpl {

namespace {

// A message that is not this run's (the nodes' rule: channels::OfRun).
bool OfAnotherRun(const std::string& channel, const uint8_t* data, size_t size, int64_t run_id) {
  return !channels::OfRun(run_id, RunIdOf(data, size), channels::IsLoopChannel(channel));
}

}  // namespace

LogRecorder::LogRecorder(LcmBus* bus, const RecordOptions& options)
    : filter_(options.policy), bus_(bus), run_id_(options.run_id) {
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
  subscriptions_.push_back(bus->SubscribeEveryBus(
      options.channels,
      [this](const lcm::ReceiveBuffer* rbuf, const std::string& ch) { OnMessage(rbuf, ch); },
      1 << 20));
  subscriptions_.push_back(bus->Subscribe(
      channels::kRecordLedger,
      [this](const lcm::ReceiveBuffer* rbuf, const std::string& ch) { OnLedger(rbuf, ch); },
      1 << 12));
}

bool LogRecorder::SureItIsLost(const std::string& publisher, const LedgerEntry& entry,
                               bool stopping) {
  // What the recorder lacks may still wait in its sockets (it reads its buses one after the
  // other, and may fall behind). A channel's messages arrive in order: once a later seq has
  // arrived, an earlier one missing is lost. A stopping publisher sends nothing later: its last
  // messages count as lost when its final ledger comes a second time, 20 ms on.
  if (received_record_.newest(entry.channel) > entry.through_seq) return true;
  if (!stopping) return false;
  auto [it, first] = final_ledgers_.try_emplace(publisher + "/" + entry.channel, entry);
  const bool again = !first && it->second.after_seq == entry.after_seq &&
                     it->second.through_seq == entry.through_seq;
  it->second = entry;
  return again;
}

void LogRecorder::OnLedger(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  record_ledger_t ledger;
  if (!DecodeMessage(rbuf->data, rbuf->data_size, &ledger)) return;  // garbage: no receipt
  const record_ledger_t* m = &ledger;
  if (run_id_ != 0 && m->run_id != run_id_) return;  // another run's publisher
  const size_t n = static_cast<size_t>(std::max<int16_t>(m->num_channels, 0));
  for (size_t i = 0; i < n; ++i) {
    const LedgerEntry entry{m->channel[i], m->after_seq[i], m->through_seq[i], m->count[i]};
    const Receipt r = received_record_.Answer(entry);
    if (!r.complete && !SureItIsLost(m->publisher, entry, m->stopping != 0)) continue;
    record_receipt_t out;
    out.run_id = run_id_;
    out.utime = WallMicros();
    out.seq = -1;
    out.publisher = m->publisher;
    out.channel = r.channel;
    out.complete = r.complete;
    out.after_seq = r.after_seq;
    out.through_seq = r.through_seq;
    out.num_have = static_cast<int32_t>(r.have.size());
    out.have = r.have;
    if (!r.complete) asked_again_ += m->count[i] - out.num_have;
    bus_->Publish(channels::kRecordReceipt, out);
  }
}

LogRecorder::~LogRecorder() {
  for (int id : subscriptions_) bus_->Unsubscribe(id);
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

bool LogRecorder::IsCopy(const std::string& channel, uint64_t hash) {
  // For a message without a seq: one of a node's last 8, sent again within about a second
  // (resend.h); the window is wide enough that other traffic on the channel (garbage, a
  // forger's) cannot push the original out of it first.
  constexpr size_t kRemembered = 512;
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
  if (channel == channels::kRecordLedger || channel == channels::kRecordReceipt) return;
  const auto* data = static_cast<const uint8_t*>(rbuf->data);
  if (OfAnotherRun(channel, data, rbuf->data_size, run_id_)) {
    ++foreign_;
    return;
  }
  // A copy (sent again by the loop, or at this recorder's request) is recorded once: told by its
  // seq and bytes, or, without a seq, by its bytes among the channel's latest.
  const uint64_t hash = HashBytes(data, rbuf->data_size);
  const auto verdict = received_record_.Add(channel, SeqOf(data, rbuf->data_size), hash);
  if (verdict == ReceivedRecord::Verdict::kCopy ||
      (verdict == ReceivedRecord::Verdict::kUnknown && IsCopy(channel, hash))) {
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
