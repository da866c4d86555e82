#pragma once
// The buses of one process, one per channel group (channels.h), and how a node publishes and
// subscribes on them. With a udpm URL each bus is an LCM instance on its own port (base + 1000 *
// bus); with any other network URL (or `separate` off) every bus is the one instance. With
// memq:// every node is in this process, and messages travel through an InProcessQueue instead
// of LCM (the same delivery rules, no pipe, no copies).
#include <memory>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "components/runtime/inprocess_queue.h"

namespace dmpl {

class LcmBus {
 public:
  using Handler = InProcessQueue::Handler;

  LcmBus(std::string base_url, bool separate);
  ~LcmBus();
  LcmBus(const LcmBus&) = delete;
  LcmBus& operator=(const LcmBus&) = delete;

  template <typename Msg>
  void Publish(const std::string& channel, const Msg& msg) {
    if (queue_) {
      queue_->Publish(channel, msg);
    } else {
      For(channel).publish(channel, &msg);
    }
  }
  void Publish(const std::string& channel, const void* data, unsigned size);

  // Subscribes `handler` to `channel` on the bus it travels on; returns an id for Unsubscribe.
  // `queue_capacity` > 0: how many of its messages LCM keeps while the process is busy.
  int Subscribe(const std::string& channel, Handler handler, int queue_capacity = 0);
  // The same for every channel `pattern` matches (a regex over the whole name), on every bus:
  // a recorder.
  int SubscribeEveryBus(const std::string& pattern, Handler handler, int queue_capacity = 0);
  void Unsubscribe(int id);

  // memq://: the in-process queue the executor delivers from (null on a network bus).
  InProcessQueue* in_process() { return queue_.get(); }

  // A network bus's LCM instances. The instance a channel travels on (created on first use).
  lcm::LCM& For(const std::string& channel);
  // Every bus (creates the missing ones): for a recorder.
  std::vector<lcm::LCM*> All();
  // The instances subscribed on, management first (the executor polls these).
  std::vector<lcm::LCM*> listened() const;
  bool good();
  const std::string& url() const { return base_url_; }

  // The URL of bus `bus` for a base URL (the base itself for bus 0 or a non-udpm URL).
  static std::string UrlFor(const std::string& base_url, int bus);
  static int BusOf(const std::string& channel);

 private:
  // One LCM subscription: LCM calls On, which calls the handler.
  struct LcmSubscription {
    int id;
    lcm::LCM* lcm;
    lcm::Subscription* subscription;
    Handler handler;
    void On(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      handler(rbuf, channel);
    }
  };
  lcm::LCM& Get(int bus);
  // The instance to subscribe on for `channel`: the bus is then polled. LCM starts receiving a
  // bus's traffic only when asked to, so a bus a process only publishes on costs it nothing.
  lcm::LCM& Listen(const std::string& channel);
  void SubscribeOn(lcm::LCM* lcm, int id, const std::string& pattern, Handler handler,
                   int queue_capacity);

  std::string base_url_;
  bool separate_;
  std::unique_ptr<InProcessQueue> queue_;
  std::vector<std::unique_ptr<lcm::LCM>> instances_;
  std::vector<bool> listened_;
  std::vector<std::unique_ptr<LcmSubscription>> subscriptions_;
  int next_id_ = 1;
};

}  // namespace dmpl
