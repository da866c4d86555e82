#include "tools/calibrate/log_data.h"

#include <stdexcept>

#include "components/logging/decode.h"
#include "components/logging/event_log_reader.h"
#include "components/runtime/channels.h"
#include "components/runtime/lcm_eigen.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/hand_sensors_t.hpp"

namespace dmpl::calib {
namespace {

std::vector<TipSample> Tips(const tactile_t& m) {
  std::vector<TipSample> out;
  for (const auto& f : m.fingers) {
    out.push_back({f.in_contact != 0, ToVector3(f.position), f.force_n});
  }
  return out;
}

}  // namespace

LogData ReadLogs(const std::vector<std::string>& paths) {
  LogData data;
  int64_t offset = 0;
  for (const std::string& path : paths) {
    EventLogReader log(path);  // skips garbage, stops at a torn last event
    data.sources.push_back(path);
    int64_t max_seq = -1;
    LogEvent event;
    while (log.Next(&event)) {
      const LogEvent* e = &event;
      ++data.messages;
      const std::string channel(e->channel);
      if (channel == channels::kSensors || channel == channels::kSensorsTrue) {
        hand_sensors_t m;
        if (DecodeMessage(e->data, static_cast<uint32_t>(e->size), &m)) {
          Tick& tick = data.ticks[offset + m.seq];
          tick.t = m.utime * 1e-6;
          if (data.fingers.empty()) {
            for (const auto& f : m.tactile.fingers) data.fingers.push_back(f.finger);
          }
          if (channel == channels::kSensors) {
            tick.sensed = Tips(m.tactile);
            tick.has_sensed = true;
            if (m.object.valid) {
              tick.object_position = ToVector3(m.object.position);
              tick.has_object = true;
            }
          } else {
            tick.truth = Tips(m.tactile);
            tick.has_truth = true;
          }
          max_seq = std::max<int64_t>(max_seq, m.seq);
        }
      } else if (channel == channels::kControllerStatus) {
        controller_status_t m;
        if (DecodeMessage(e->data, static_cast<uint32_t>(e->size), &m)) {
          Tick& tick = data.ticks[offset + m.seq];
          tick.control.clear();
          for (const auto& f : m.fingers) {
            ControlSample c;
            c.role = f.role;
            c.primitive = f.primitive;
            c.in_contact = f.in_contact != 0;
            c.force = f.force_n;
            c.desired = f.desired_force_n;
            c.tip = ToVector3(f.tip_position);
            c.target = ToVector3(f.target_position);
            c.contact = ToVector3(f.contact_position);
            tick.control.push_back(c);
          }
          tick.has_control = true;
        }
      }
    }
    offset += max_seq + 1000;
  }
  return data;
}

}  // namespace dmpl::calib
