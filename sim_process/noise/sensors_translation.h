#pragma once
// hand_sensors_t <-> HandReading: the noise injector's messages and its core's values, written
// once (the node and the fuzz test translate through here).
#include <optional>
#include <string>

#include "dmpl/hand_sensors_t.hpp"
#include "sim_process/noise/hand_reading.h"

namespace dmpl {

// The reading a message carries, or nullopt with why when it is not one tick's (its parts
// disagree on the tick, or on their own sizes).
std::optional<HandReading> ToReading(const hand_sensors_t& m, std::string* why);
// The message of a reading (run_id left 0: the node's to set).
hand_sensors_t ToMessage(const HandReading& r);

}  // namespace dmpl
