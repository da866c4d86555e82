#include "components/runtime/inprocess_queue.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "components/runtime/check.h"
#include "components/runtime/clock.h"

namespace dmpl {

int InProcessQueue::Subscribe(const std::string& channel_pattern, Handler handler) {
  DMPL_DEMAND(!delivering_);
  subscriptions_.push_back({next_id_, std::regex(channel_pattern), std::move(handler)});
  subscribers_of_.clear();
  return next_id_++;
}

void InProcessQueue::Unsubscribe(int id) {
  DMPL_DEMAND(!delivering_);
  subscriptions_.erase(std::remove_if(subscriptions_.begin(), subscriptions_.end(),
                                      [id](const Subscription& s) { return s.id == id; }),
                       subscriptions_.end());
  subscribers_of_.clear();
}

InProcessQueue::Message& InProcessQueue::Enqueue(const std::string& channel, size_t size) {
  if (spare_.empty()) {
    queue_.emplace_back();
  } else {
    queue_.push_back(std::move(spare_.back()));
    spare_.pop_back();
  }
  Message& m = queue_.back();
  m.channel = channel;
  m.bytes.resize(size);
  m.utime = WallMicros();
  return m;
}

void InProcessQueue::Publish(const std::string& channel, const void* data, size_t size) {
  Message& m = Enqueue(channel, size);
  if (size > 0) std::memcpy(m.bytes.data(), data, size);
}

const std::vector<size_t>& InProcessQueue::SubscribersOf(const std::string& channel) {
  auto [it, inserted] = subscribers_of_.try_emplace(channel);
  if (inserted) {
    for (size_t i = 0; i < subscriptions_.size(); ++i) {
      if (std::regex_match(channel, subscriptions_[i].pattern)) it->second.push_back(i);
    }
  }
  return it->second;
}

bool InProcessQueue::DeliverOne() {
  DMPL_DEMAND(!delivering_);  // a handler publishes; it never delivers
  if (queue_.empty()) return false;
  Message m = std::move(queue_.front());
  queue_.pop_front();
  lcm::ReceiveBuffer rbuf{m.bytes.data(), static_cast<uint32_t>(m.bytes.size()), m.utime};
  struct Delivering {
    bool* flag;
    explicit Delivering(bool* f) : flag(f) { *flag = true; }
    ~Delivering() { *flag = false; }
  } delivering(&delivering_);
  for (size_t i : SubscribersOf(m.channel)) subscriptions_[i].handler(&rbuf, m.channel);
  spare_.push_back(std::move(m));
  return true;
}

}  // namespace dmpl
