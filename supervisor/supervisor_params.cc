#include "supervisor/supervisor_params.h"

#include <string>

#include "components/runtime/check.h"

namespace dmpl {

void TaskParams::Validate(const std::string& source) const {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'task." + key + "': " + what);
  };
  if (!std::isfinite(angle)) fail("angle", "must be finite");
  if (!(step > 0) || step > 1.0) fail("step", "must be in (0, 1] rad");
  if (turn != "three" && turn != "four" && turn != "continuous" && turn != "auto") {
    fail("turn", "must be 'auto', 'continuous', 'four' or 'three' (the paper's)");
  }
  if (!(angular_speed > 0)) fail("angular_speed", "must be > 0");
  if (!(overlap_angular_speed >= 0)) fail("overlap_angular_speed", "must be >= 0");
  if (explore_force_n < 0) fail("explore_force_n", "must be >= 0");
  if (explore_travel < 0) fail("explore_travel", "must be >= 0");
  if (random_goals < 0 || random_goals > 100000) fail("random_goals", "must be in [0, 100000]");
  if (!(random_goal_separation_rad >= 0) || random_goal_separation_rad > 3.0) {
    fail("random_goal_separation_rad", "must be in [0, 3] rad (further apart is rare)");
  }
  if (!(goal_tolerance_rad > 0) || goal_tolerance_rad > M_PI) {
    fail("goal_tolerance_rad", "must be in (0, pi]");
  }
  if (!(goal_hold_s >= 0)) fail("goal_hold_s", "must be >= 0");
}

bool TaskParams::has_goals() const { return !goals.empty() || random_goals > 0; }

}  // namespace dmpl
