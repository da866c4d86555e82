#include "components/runtime/lcm_bus.h"

#include <algorithm>
#include <cstring>

#include "components/runtime/channels.h"
#include "components/runtime/check.h"
#include "components/runtime/lcm_url.h"

namespace dmpl {

LcmBus::LcmBus(std::string base_url, bool separate)
    : base_url_(std::move(base_url)),
      separate_(separate && base_url_.rfind("udpm://", 0) == 0),
      instances_(channels::kNumBuses),
      listened_(channels::kNumBuses, false) {
  if (base_url_.rfind("memq://", 0) == 0) queue_ = std::make_unique<InProcessQueue>();
}

LcmBus::~LcmBus() {
  for (const auto& s : subscriptions_) s->lcm->unsubscribe(s->subscription);
}

int LcmBus::BusOf(const std::string& channel) {
  for (const auto& cb : channels::kChannelBuses) {
    if (channel == cb.channel) return cb.bus;
  }
  return 0;  // anything else (tests, tools) on the management bus
}

std::string LcmBus::UrlFor(const std::string& base_url, int bus) {
  std::string why;
  const std::optional<std::string> url = BusUrl(base_url, bus, &why);
  DMPL_THROW_UNLESS(url.has_value(), why);
  return *url;
}

lcm::LCM& LcmBus::Get(int bus) {
  DMPL_DEMAND(!queue_);  // an in-process bus has no LCM instance
  const int b = separate_ ? bus : 0;
  if (!instances_[b]) instances_[b] = std::make_unique<lcm::LCM>(UrlFor(base_url_, b));
  return *instances_[b];
}

lcm::LCM& LcmBus::For(const std::string& channel) { return Get(BusOf(channel)); }

lcm::LCM& LcmBus::Listen(const std::string& channel) {
  const int b = separate_ ? BusOf(channel) : 0;
  listened_[b] = true;
  return Get(b);
}

void LcmBus::Publish(const std::string& channel, const void* data, unsigned size) {
  if (queue_) {
    queue_->Publish(channel, data, size);
  } else {
    For(channel).publish(channel, data, size);
  }
}

void LcmBus::SubscribeOn(lcm::LCM* lcm, int id, const std::string& pattern, Handler handler,
                         int queue_capacity) {
  auto s =
      std::make_unique<LcmSubscription>(LcmSubscription{id, lcm, nullptr, std::move(handler)});
  s->subscription = lcm->subscribe(pattern, &LcmSubscription::On, s.get());
  DMPL_THROW_UNLESS(s->subscription != nullptr,
                    "LCM refused a subscription to '" << pattern << "'");
  if (queue_capacity > 0) s->subscription->setQueueCapacity(queue_capacity);
  subscriptions_.push_back(std::move(s));
}

int LcmBus::Subscribe(const std::string& channel, Handler handler, int queue_capacity) {
  if (queue_) return queue_->Subscribe(channel, std::move(handler));
  const int id = next_id_++;
  SubscribeOn(&Listen(channel), id, channel, std::move(handler), queue_capacity);
  return id;
}

int LcmBus::SubscribeEveryBus(const std::string& pattern, Handler handler, int queue_capacity) {
  if (queue_) return queue_->Subscribe(pattern, std::move(handler));
  const int id = next_id_++;
  for (lcm::LCM* l : All()) SubscribeOn(l, id, pattern, handler, queue_capacity);
  return id;
}

void LcmBus::Unsubscribe(int id) {
  if (queue_) {
    queue_->Unsubscribe(id);
    return;
  }
  for (const auto& s : subscriptions_) {
    if (s->id == id) s->lcm->unsubscribe(s->subscription);
  }
  subscriptions_.erase(std::remove_if(subscriptions_.begin(), subscriptions_.end(),
                                      [id](const auto& s) { return s->id == id; }),
                       subscriptions_.end());
}

std::vector<lcm::LCM*> LcmBus::listened() const {
  std::vector<lcm::LCM*> out;
  for (size_t b = 0; b < instances_.size(); ++b) {
    if (instances_[b] && listened_[b]) out.push_back(instances_[b].get());
  }
  return out;
}

std::vector<lcm::LCM*> LcmBus::All() {
  std::vector<lcm::LCM*> out;
  for (int b = 0; b < (separate_ ? channels::kNumBuses : 1); ++b) {
    listened_[b] = true;
    out.push_back(&Get(b));
  }
  return out;
}

bool LcmBus::good() {
  if (queue_) return true;
  for (const auto& i : instances_) {
    if (i && !i->good()) return false;
  }
  return Get(0).good();
}

}  // namespace dmpl
