#include "components/runtime/sim_request.h"

#include "dmpl/sim_control_t.hpp"

namespace dmpl {

// The codes are the message's: a change to one side fails to compile here.
static_assert(static_cast<int8_t>(SimRequest::kRelease) == sim_control_t::RELEASE);
static_assert(static_cast<int8_t>(SimRequest::kHold) == sim_control_t::HOLD);
static_assert(static_cast<int8_t>(SimRequest::kReset) == sim_control_t::RESET);
static_assert(static_cast<int8_t>(SimRequest::kPause) == sim_control_t::PAUSE);
static_assert(static_cast<int8_t>(SimRequest::kResume) == sim_control_t::RESUME);
static_assert(static_cast<int8_t>(SimRequest::kStop) == sim_control_t::STOP);

const char* ToString(SimRequest request) {
  switch (request) {
    case SimRequest::kNone: return "none";
    case SimRequest::kRelease: return "release";
    case SimRequest::kHold: return "hold";
    case SimRequest::kReset: return "reset";
    case SimRequest::kPause: return "pause";
    case SimRequest::kResume: return "resume";
    case SimRequest::kStop: return "stop";
  }
  return "unknown";
}

}  // namespace dmpl
