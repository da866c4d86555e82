#pragma once
// Which finger explores next. The gait's rule is reach: the finger the next step would take
// furthest from its home (GaitGeometry::FurthestFromHome), so that no finger rides out of its
// workspace. Under gravity a second rule weighs in: the finger that leaves must leave a grasp
// that still holds the weight. Among the fingers nearly as far from home as the furthest, the
// one whose absence leaves the most support along the sensed gravity (SupportAlong) explores.
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
};

// The next explorer (not `skip`; -1: none) for a step of `step` rad about `axis`: of the
// fingers in contact whose deviation after the step is within `slack_rad` of the furthest's,
// the one whose lifting leaves the most support along view.gravity within `limits`; the
// furthest on a tie, with `slack_rad` 0, or while gravity is not sensed.
ExplorerChoice NextExplorer(const GaitGeometry& geometry, const Eigen::Vector3d& axis,
                            double step, int skip, const ControllerView& view,
                            const SupportLimits& limits, double slack_rad);

}  // namespace dmpl
