#include "supervisor/supervisor_params.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "components/runtime/check.h"

namespace dmpl {

SupportLimits SupportParams::Limits(double observed_friction) const {
  const bool use_observed = observed && observed_friction > 0.0;
  return {use_observed ? std::clamp(observed_friction, min_observed, max_observed) : friction, 0.0,
          max_push_n};
}

// The bounds of single keys are declared beside them (supervisor_params.h).
void TaskParams::Validate(const std::string& source) const {
  CheckBounds(*this, source, "task");
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'task." + key + "': " + what);
  };
  if (!std::isfinite(angle)) fail("angle", "must be finite");
  const ContactChoiceParams& choice = contact_choice;
  if (!choice.enabled && (choice.clear_steps || choice.extend_surface_m > 0)) {
    fail(choice.clear_steps ? "contact_choice.clear_steps" : "contact_choice.extend_surface_m",
         "needs task.contact_choice.enabled: true (the chooser's IK and link model)");
  }
  if (support.min_observed > support.max_observed) {
    fail("support.min_observed", "must not exceed task.support.max_observed");
  }
  if (explorer_support.check_ride && !(explorer_support.slack_rad > 0)) {
    fail("explorer_support.check_ride",
         "needs task.explorer_support.slack_rad > 0 (it checks the finger the support rule keeps "
         "gripping; without the rule there is none)");
  }
}

bool TaskParams::has_goals() const { return !goals.empty() || random_goals > 0; }

}  // namespace dmpl
