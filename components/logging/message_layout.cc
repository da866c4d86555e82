#include "components/logging/message_layout.h"

#include <unordered_set>

#include "dmpl/controller_status_t.hpp"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/joint_cmd_t.hpp"
#include "dmpl/sim_control_t.hpp"
#include "dmpl/task_cmd_t.hpp"

namespace dmpl {
namespace {

int64_t BigEndian64(const void* data, size_t offset) {
  const auto* p = static_cast<const uint8_t*>(data) + offset;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<int64_t>(v);
}

}  // namespace

bool CarriesRunId(const void* data, size_t size) {
  static const std::unordered_set<int64_t> kTypesWithRunId = {
      controller_status_t::getHash(), finger_targets_t::getHash(), hand_sensors_t::getHash(),
      heartbeat_t::getHash(),         joint_cmd_t::getHash(),      sim_control_t::getHash(),
      task_cmd_t::getHash()};
  return size >= 16 && kTypesWithRunId.count(BigEndian64(data, 0)) != 0;
}

int64_t RunIdOf(const void* data, size_t size) {
  return CarriesRunId(data, size) ? BigEndian64(data, 8) : 0;
}

int64_t SeqOf(const void* data, size_t size) {
  const size_t at = CarriesRunId(data, size) ? 24 : 16;
  return size >= at + 8 ? BigEndian64(data, at) : -1;
}

size_t HeaderSize(const void* data, size_t size) {
  const size_t header = CarriesRunId(data, size) ? 32 : 24;
  return size < header ? size : header;
}

}  // namespace dmpl
