// Fuzzing what a node does with bytes from the bus: 10^5 random and mutated packets per message
// type through DecodeMessage (the nodes' only decode path), and the decoded truth messages
// through the noise injector. Nothing may crash (run under ASan/UBSan with
// `tools/dmpl test --sanitize`); bad bytes are a failed decode. The mutations are those a network
// or a forger makes: bits flipped, bytes overwritten (array lengths negative or huge), packets
// cut or extended, random bytes behind a valid type hash.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "components/logging/decode.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/joint_cmd_t.hpp"
#include "dmpl/sim_control_t.hpp"
#include "dmpl/task_cmd_t.hpp"
#include "sim_process/noise/noise_injector.h"
#include "sim_process/noise/sensors_translation.h"

namespace dmpl {
namespace {

constexpr int kPackets = 100000;
const std::vector<std::string> kFingers = {"T", "F", "M", "R"};

std::vector<std::string> JointNames() {
  std::vector<std::string> names;
  for (const auto& f : kFingers) {
    for (int j = 0; j < 4; ++j) names.push_back(f + "_j" + std::to_string(j));
  }
  return names;
}

hand_sensors_t Sensors() {
  hand_sensors_t m{};
  m.seq = 42;
  m.joints.name = JointNames();
  m.joints.num_joints = static_cast<int16_t>(m.joints.name.size());
  m.joints.position.assign(m.joints.name.size(), 0.3);
  m.joints.velocity.assign(m.joints.name.size(), 0.0);
  m.joints.effort.assign(m.joints.name.size(), 0.1);
  m.object.valid = true;
  m.object.orientation[0] = 1.0;
  m.tactile.num_fingers = static_cast<int8_t>(kFingers.size());
  m.tactile.fingers.resize(kFingers.size());
  for (size_t f = 0; f < kFingers.size(); ++f) {
    m.tactile.fingers[f].finger = kFingers[f];
    m.tactile.fingers[f].in_contact = true;
    m.tactile.fingers[f].force_n = 0.8;
  }
  return m;
}

joint_cmd_t Command() {
  joint_cmd_t m{};
  m.seq = 42;
  m.name = JointNames();
  m.num_joints = static_cast<int16_t>(m.name.size());
  m.position.assign(m.name.size(), 0.3);
  return m;
}

// A message with one entry per finger, each named (finger targets, task, report).
template <typename Msg>
Msg PerFinger(int64_t seq) {
  Msg m{};
  m.seq = seq;
  m.num_fingers = static_cast<int8_t>(kFingers.size());
  m.fingers.resize(kFingers.size());
  for (size_t f = 0; f < kFingers.size(); ++f) m.fingers[f].finger = kFingers[f];
  return m;
}

finger_targets_t Targets() {
  auto m = PerFinger<finger_targets_t>(42);
  m.num_joints = 16;
  m.joint_position.assign(16, 0.3);
  return m;
}

task_cmd_t Task() {
  auto m = PerFinger<task_cmd_t>(42);
  m.name = "A4 R explore";
  m.sim_command_reason = "grasp stable";
  return m;
}

controller_status_t Report() {
  auto m = PerFinger<controller_status_t>(40);
  m.events.resize(2);
  m.events[0].text = "R touches";
  m.num_events = 2;
  return m;
}

template <typename Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())),
            static_cast<int>(bytes.size()));
  return bytes;
}

// One mutation of `valid`, as a network or a forger would make it.
std::vector<uint8_t> Mutate(const std::vector<uint8_t>& valid, std::mt19937_64* rng) {
  std::vector<uint8_t> p = valid;
  auto pick = [rng](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(*rng); };
  auto byte = [rng] { return static_cast<uint8_t>((*rng)() & 0xFF); };
  switch (pick(6)) {
    case 0:  // bits flipped
      for (size_t i = 0, n = 1 + pick(8); i < n; ++i) p[pick(p.size())] ^= 1u << pick(8);
      break;
    case 1:  // bytes overwritten: lengths and counts become negative, huge or zero
      for (size_t i = 0, n = 1 + pick(4); i < n; ++i) {
        const uint8_t extreme[] = {0x00, 0x7F, 0x80, 0xFF};
        p[8 + pick(p.size() - 8)] = pick(2) ? extreme[pick(4)] : byte();
      }
      break;
    case 2:  // cut
      p.resize(pick(p.size()));
      break;
    case 3:  // extended
      for (size_t i = 0, n = 1 + pick(64); i < n; ++i) p.push_back(byte());
      break;
    case 4:  // random bytes behind the valid type hash
      for (size_t i = 8; i < p.size(); ++i) p[i] = byte();
      break;
    default:  // random bytes
      p.resize(pick(2 * valid.size() + 1));
      for (auto& b : p) b = byte();
  }
  return p;
}

template <typename Msg, typename Use>
void Fuzz(const Msg& sample, Use use) {
  const std::vector<uint8_t> valid = Encode(sample);
  std::mt19937_64 rng(7);
  int decoded = 0;
  for (int i = 0; i < kPackets; ++i) {
    const std::vector<uint8_t> packet = Mutate(valid, &rng);
    Msg msg;
    if (DecodeMessage(packet.data(), static_cast<uint32_t>(packet.size()), &msg)) {
      ++decoded;
      use(msg);
    }
  }
  Msg msg;
  EXPECT_TRUE(DecodeMessage(valid.data(), static_cast<uint32_t>(valid.size()), &msg));
  // Some mutations still decode (a flipped bit in a number): the decode path was exercised past
  // the hash, and those messages went on to their use.
  EXPECT_GT(decoded, 0) << Msg::getTypeName();
  EXPECT_LT(decoded, kPackets) << Msg::getTypeName();
}

TEST(DecodeFuzzTest, TruthThroughTheNoiseInjector) {
  NoiseParams params;
  NoiseInjector noise(params, 1);
  Fuzz(Sensors(), [&noise](const hand_sensors_t& m) {
    std::string why;
    if (const auto reading = ToReading(m, &why)) {
      if (const auto sensed = noise.Sense(*reading)) ToMessage(*sensed);
    }
  });
}

TEST(DecodeFuzzTest, EveryTypeANodeReads) {
  auto nothing = [](const auto&) {};
  Fuzz(Command(), nothing);
  Fuzz(Targets(), nothing);
  Fuzz(Task(), nothing);
  Fuzz(Report(), nothing);
  sim_control_t control{};
  control.reason = "test";
  Fuzz(control, nothing);
  heartbeat_t beat{};
  beat.process = "dmpl_ik";
  Fuzz(beat, nothing);
}

}  // namespace
}  // namespace dmpl
