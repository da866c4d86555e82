#pragma once
// The LCM instances of one process, one per bus (channels.h): channel -> the LCM it travels on.
// With a udpm URL each bus has its own port (base + 1000 * bus); with any other URL (memq://,
// or `separate` off) every bus is the one instance.
#include <memory>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace dmpl {

class LcmBus {
 public:
  LcmBus(std::string base_url, bool separate);
  LcmBus(const LcmBus&) = delete;
  LcmBus& operator=(const LcmBus&) = delete;

  // The instance a channel travels on (created on first use), to publish on.
  lcm::LCM& For(const std::string& channel);
  // The same, to subscribe on: the bus is then polled. LCM starts receiving a bus's traffic only
  // when asked to, so a bus a process only publishes on costs it nothing.
  lcm::LCM& Listen(const std::string& channel);
  lcm::LCM& management() { return Get(0); }
  // Every bus (creates the missing ones): for a recorder.
  std::vector<lcm::LCM*> All();
  // The instances created so far, management first.
  std::vector<lcm::LCM*> created() const;
  // The instances subscribed on, management first (the executor polls these).
  std::vector<lcm::LCM*> listened() const;
  bool good();
  const std::string& url() const { return base_url_; }

  // The URL of bus `bus` for a base URL (the base itself for bus 0 or a non-udpm URL).
  static std::string UrlFor(const std::string& base_url, int bus);
  static int BusOf(const std::string& channel);

 private:
  lcm::LCM& Get(int bus);
  std::string base_url_;
  bool separate_;
  std::vector<std::unique_ptr<lcm::LCM>> instances_;
  std::vector<bool> listened_;
};

}  // namespace dmpl
