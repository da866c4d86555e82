#include "components/runtime/lcm_bus.h"

#include <cstring>

#include "components/runtime/channels.h"
#include "components/runtime/check.h"
#include "components/runtime/lcm_url.h"

namespace dmpl {

LcmBus::LcmBus(std::string base_url, bool separate)
    : base_url_(std::move(base_url)),
      separate_(separate && base_url_.rfind("udpm://", 0) == 0),
      instances_(channels::kNumBuses),
      listened_(channels::kNumBuses, false) {}

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

std::vector<lcm::LCM*> LcmBus::created() const {
  std::vector<lcm::LCM*> out;
  for (const auto& i : instances_) {
    if (i) out.push_back(i.get());
  }
  return out;
}

bool LcmBus::good() {
  for (lcm::LCM* l : created()) {
    if (!l->good()) return false;
  }
  return management().good();
}

}  // namespace dmpl
