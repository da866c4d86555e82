#include "components/runtime/resend.h"

#include <algorithm>

namespace dmpl {

namespace {
constexpr double kMaxBackoffS = 1.0;
}  // namespace

Resender::Resender(size_t depth, double stall_s)
    : depth_(std::max<size_t>(depth, 1)), stall_s_(stall_s) {}

void Resender::PublishBytes(lcm::LCM& lcm, const std::string& channel, std::vector<uint8_t> bytes,
                            double now) {
  lcm.publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size()));
  if (!enabled()) return;
  kept_.push_back({&lcm, channel, std::move(bytes)});
  while (kept_.size() > depth_) kept_.pop_front();
  backoff_s_ = stall_s_;
  next_resend_ = now + backoff_s_;
}

int Resender::Poll(double now) {
  if (!enabled() || kept_.empty() || now < next_resend_) return 0;
  for (Kept& k : kept_) {
    k.lcm->publish(k.channel, k.bytes.data(), static_cast<unsigned int>(k.bytes.size()));
  }
  resent_ += static_cast<int64_t>(kept_.size());
  backoff_s_ = std::min(backoff_s_ * 2, kMaxBackoffS);
  next_resend_ = now + backoff_s_;
  return static_cast<int>(kept_.size());
}

}  // namespace dmpl
