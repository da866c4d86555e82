#pragma once
// Lockstep over a lossy network (README, "Lockstep and real time"): a node keeps the last
// messages it sent on the loop's channels and sends the same bytes again while the loop stalls.
// Whoever lost one gets it again; every receiver drops the copies it already has by their seq,
// and nothing is ever computed twice, so a run that lost messages gives the results of one that
// did not. The stall is the node's own view: no new message of its own for `stall_s`; it sends
// again after stall_s, then 2, 4, ... times as long (at most a second) until it sends a new one.
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace dmpl {

// A message's LCM encoding.
template <typename Msg>
std::vector<uint8_t> Encode(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

class Resender {
 public:
  // depth: how many of the last messages are kept (all channels together); stall_s <= 0: never
  // sends again (real time, where a lost message is simply superseded by the next).
  Resender(size_t depth, double stall_s);

  // Encodes `msg` once, publishes it and keeps the bytes; `now` is the monotonic clock.
  template <typename Msg>
  void Publish(lcm::LCM& lcm, const std::string& channel, const Msg& msg, double now) {
    PublishBytes(lcm, channel, Encode(msg), now);
  }
  // The same for bytes already encoded.
  void PublishBytes(lcm::LCM& lcm, const std::string& channel, std::vector<uint8_t> bytes,
                    double now);

  // From a timer: sends every kept message again (oldest first) when the node has stalled.
  // Returns how many it sent.
  int Poll(double now);

  int64_t resent() const { return resent_; }
  bool enabled() const { return stall_s_ > 0; }

 private:
  struct Kept {
    lcm::LCM* lcm;
    std::string channel;
    std::vector<uint8_t> bytes;
  };

  size_t depth_;
  double stall_s_;
  std::deque<Kept> kept_;
  double next_resend_ = 0;
  double backoff_s_ = 0;
  int64_t resent_ = 0;
};

}  // namespace dmpl
