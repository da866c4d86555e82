#pragma once
// Which finger explores next. The gait's rule is reach: the finger the next step would take
// furthest from its home (GaitGeometry::FurthestFromHome), so that no finger rides out of its
// workspace. Under gravity a second rule weighs in: the finger that leaves must leave a grasp
// that still holds the weight. Among the fingers nearly as far from home as the furthest, the
// one whose absence leaves the most support along the sensed gravity (SupportAlong) explores,
// when the furthest's absence would leave less than the grasp needs.
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "components/controller/grasp_support.h"
#include "supervisor/gait_geometry.h"
#include "supervisor/supervisor_types.h"

namespace dmpl {

struct ExplorerChoice {
  int finger = -1;     // -1: none (no finger to choose)
  int furthest = -1;   // the reach rule's finger
  double support_n = 0.0;           // what the others hold along gravity without `finger`
  double furthest_support_n = 0.0;  // and without `furthest`
  // A finger in contact had no sensed point: the support rule gave no verdict (ask again).
  bool grasp_unknown = false;
};

// When the furthest finger may wait, gripping, while another explores for the support it leaves.
struct WaitRule {
  double slack_rad = 0.0;  // 0: never (the reach rule alone)
  double need_n = std::numeric_limits<double>::infinity();
  double palm_side_rad = M_PI / 2;
  double max_contact_angle_rad = M_PI;
};

// The next explorer (not `skip`; -1: none) for a step of `step` rad about `axis`: of the
// fingers in contact whose deviation after the step is within `rule.slack_rad` of the
// furthest's, the one whose lifting leaves the most support along view.gravity within
// `limits`. The furthest while its absence leaves at least `rule.need_n`, while its contact
// lies more than `rule.palm_side_rad` toward the palm from the level through the centre
// (PalmSideElevation: its links come near the object there, and it must move), while its
// contact lies more than `rule.max_contact_angle_rad` round its tip (FingerView::ContactAngle:
// riding on, its links come to the object), while a finger in contact has no sensed point
// (FingerView::SensesPoint: the grasp is not known), on a tie, with no slack, or while gravity
// is not sensed.
ExplorerChoice NextExplorer(const GaitGeometry& geometry, const Eigen::Vector3d& axis,
                            double step, int skip, const ControllerView& view,
                            const SupportLimits& limits, const WaitRule& rule);

// The elevation (rad) of finger `f`'s contact above the plane through the object's centre
// parallel to the palm (palm frame: x is the palm's normal): negative toward the palm. 0
// without a sensed point (FingerView::SensesPoint).
double PalmSideElevation(int f, const ControllerView& view);

}  // namespace dmpl
