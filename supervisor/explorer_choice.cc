#include "supervisor/explorer_choice.h"

#include <algorithm>
#include <cmath>

#include "supervisor/contact_chooser.h"  // SupportWithout

namespace dmpl {

namespace {
// A support this much larger than the furthest finger's counts as larger: the LP's answers for
// one grasp agree to far better than this, and a tie keeps the reach rule.
constexpr double kMoreSupportN = 0.05;
}  // namespace

ExplorerChoice NextExplorer(const GaitGeometry& geometry, const Eigen::Vector3d& axis_in,
                            double step, int skip, const ControllerView& view,
                            const SupportLimits& limits, const WaitRule& rule) {
  ExplorerChoice choice;
  const Eigen::Vector3d axis = axis_in.normalized();
  choice.furthest = geometry.FurthestFromHome(axis, step, skip, view);
  choice.finger = choice.furthest;
  if (choice.furthest < 0 || !(rule.slack_rad > 0) || view.gravity.norm() < 0.5) return choice;
  if (PalmSideElevation(choice.furthest, view) < -rule.palm_side_rad ||
      view.fingers[choice.furthest].ContactAngle() > rule.max_contact_angle_rad) {
    return choice;
  }
  // A finger held in contact without a sensed point (the controller's debounce: a finger that
  // just stopped exploring reads nothing for a moment) leaves the grasp unknown: no verdict.
  for (const FingerView& v : view.fingers) {
    if (v.in_contact && !v.SensesPoint()) {
      choice.grasp_unknown = true;
      return choice;
    }
  }
  const Eigen::AngleAxisd turn(step, axis);
  const double reach = geometry.Deviation(choice.furthest, turn, view);
  choice.furthest_support_n = SupportWithout(view, choice.furthest, limits);
  choice.support_n = choice.furthest_support_n;
  if (choice.furthest_support_n >= rule.need_n) return choice;
  for (int k = 0; k < static_cast<int>(view.fingers.size()); ++k) {
    if (k == skip || k == choice.furthest || !view.fingers[k].in_contact) continue;
    if (geometry.Deviation(k, turn, view) < reach - rule.slack_rad) continue;
    const double support = SupportWithout(view, k, limits);
    if (support > choice.support_n + kMoreSupportN) {
      choice.finger = k;
      choice.support_n = support;
    }
  }
  return choice;
}

double PalmSideElevation(int f, const ControllerView& view) {
  const FingerView& v = view.fingers[f];
  const Eigen::Vector3d out = v.contact - view.object.translation();
  if (!v.SensesPoint() || out.norm() < 1e-9) return 0.0;
  return std::asin(std::clamp(out.normalized().x(), -1.0, 1.0));
}

}  // namespace dmpl
