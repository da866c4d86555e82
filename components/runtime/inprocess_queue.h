#pragma once
// The one-process transport (dmpl_oneprocess, node tests): LCM's delivery rules without LCM's
// memq provider. A message goes to every subscription whose pattern matches its whole channel
// name, in the order they subscribed; messages are delivered one at a time, in the order they
// were published. memq does the same but writes and polls a pipe and copies each message twice:
// ~3 us of a one-process tick (docs/benchmarks.md). Here a message is encoded once into a
// buffer that is reused, and a channel's subscribers are matched once.
#include <cstdint>
#include <deque>
#include <functional>
#include <regex>
#include <string>
#include <unordered_map>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace dmpl {

class InProcessQueue {
 public:
  using Handler = std::function<void(const lcm::ReceiveBuffer*, const std::string&)>;

  // `channel_pattern` is a regular expression over the whole channel name (as in LCM). Returns
  // the subscription's id, for Unsubscribe. Not from inside a handler.
  int Subscribe(const std::string& channel_pattern, Handler handler);
  void Unsubscribe(int id);

  void Publish(const std::string& channel, const void* data, size_t size);
  template <typename Msg>
  void Publish(const std::string& channel, const Msg& msg) {
    Message& m = Enqueue(channel, static_cast<size_t>(msg.getEncodedSize()));
    msg.encode(m.bytes.data(), 0, static_cast<int>(m.bytes.size()));
  }

  // Delivers the oldest message to its subscribers; false when nothing is queued.
  bool DeliverOne();
  size_t pending() const { return queue_.size(); }

 private:
  struct Message {
    std::string channel;
    std::vector<uint8_t> bytes;
    int64_t utime = 0;  // when it was published (LCM's recv_utime: a recorder's timestamp)
  };
  struct Subscription {
    int id;
    std::regex pattern;
    Handler handler;
  };
  // A message of `size` bytes at the queue's end, in a buffer used before when there is one.
  Message& Enqueue(const std::string& channel, size_t size);
  // The subscriptions `channel` goes to (indices into subscriptions_), matched once a channel.
  const std::vector<size_t>& SubscribersOf(const std::string& channel);

  std::vector<Subscription> subscriptions_;
  std::unordered_map<std::string, std::vector<size_t>> subscribers_of_;
  std::deque<Message> queue_;
  std::vector<Message> spare_;
  bool delivering_ = false;
  int next_id_ = 1;
};

}  // namespace dmpl
