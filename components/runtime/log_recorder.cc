#include "components/runtime/log_recorder.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dmpl {

LogRecorder::LogRecorder(LcmBus* bus, const std::string& path, const std::string& channels)
    : log_(lcm_eventlog_create(path.c_str(), "w")) {
  if (log_ == nullptr) {
    throw std::runtime_error("cannot create log file '" + path + "': " + std::strerror(errno));
  }
  for (lcm::LCM* l : bus->All()) {
    lcm::Subscription* sub = l->subscribe(channels, &LogRecorder::OnMessage, this);
    sub->setQueueCapacity(1 << 20);
    subs_.emplace_back(l, sub);
  }
}

LogRecorder::~LogRecorder() {
  for (auto& [l, sub] : subs_) l->unsubscribe(sub);
  lcm_eventlog_destroy(log_);
}

void LogRecorder::Flush() { fflush(log_->f); }

void LogRecorder::OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
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
