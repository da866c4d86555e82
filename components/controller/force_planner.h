#pragma once
// The force planner of the paper (§II.B, Fig. 2): every grip force points from its contact toward
// the centroid of the grip contacts, so the forces meet in one point and their net moment is zero;
// the magnitudes make the net force zero and none falls below a minimum (least squares around the
// nominal grip force). An exploration finger gets its own fixed small force and stays out of the
// balance: the grip fingers treat its force as zero (the paper's premise).
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace dmpl {

struct PlannedForce {
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit, into the object
  double magnitude = 0.0;                               // N
};

struct ForcePlan {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::vector<PlannedForce> forces;  // one per given contact, same order
  bool balanced = false;             // false when fewer than 2 grip contacts
};

// `contacts`: contact positions (palm frame); `grip`: which take part in the balance.
// `external`: a known force on the object the grip forces must cancel too (the exploration
// finger's fixed small push); zero in the paper.
// `aim`: the point the forces meet in; the grip contacts' centroid (the paper) when not given.
ForcePlan PlanGripForces(const std::vector<Eigen::Vector3d>& contacts,
                         const std::vector<bool>& grip, double nominal_n, double minimum_n,
                         const Eigen::Vector3d& external = Eigen::Vector3d::Zero(),
                         const std::optional<Eigen::Vector3d>& aim = std::nullopt);

// The point nearest to every grip contact's normal line (contact point + t * normal): the centre
// of a sphere, a point on a cylinder's axis. Forces aimed there push along the normals. Lines
// that do not pin a point (parallel normals: two opposed fingers) leave the free directions at
// `fallback`. Nothing when fewer than two grip contacts have a normal.
std::optional<Eigen::Vector3d> NormalsMeetingPoint(const std::vector<Eigen::Vector3d>& contacts,
                                                   const std::vector<Eigen::Vector3d>& normals,
                                                   const std::vector<bool>& grip,
                                                   const Eigen::Vector3d& fallback);

// Where a finger without contact is sent to find the object: `point` (where the grip's forces
// meet), or `fallback` (the object's estimate) when `point` lies farther from it than twice the
// farthest grip contact. Two nearly opposed normals that miss each other (an ellipsoid's skew
// pair) meet far out along their common direction, 10 cm at 5 deg and 1 cm apart: toward there a
// finger leaves the object.
Eigen::Vector3d CentreWithinReach(const Eigen::Vector3d& point, const Eigen::Vector3d& fallback,
                                  const std::vector<Eigen::Vector3d>& contacts,
                                  const std::vector<bool>& grip);

// Grip forces aimed at `aim`, within [minimum_n, maximum_n], that minimise
//   balance_weight |sum - net|^2 + |f - nominal|^2:
// with a large weight the sum is `net` wherever the bounds allow; with a moderate one an
// unbalanceable push (a finger whose opposite explores) is left to friction instead of being
// cancelled by weakening the whole grip. Bounded least squares over a few fingers, solved exactly
// by trying every set of active bounds. `balanced` when the sum is within 1 % (+ 1 mN) of `net`.
// Along `unbalanced_along` (if not zero) no balance is sought: what the sum lacks there is left
// to friction (gravity, when the squeeze is sized for the load). With a friction share the sum
// is sought anywhere within what friction can make up (FrictionShare); `balanced` counts it.
struct FrictionShare {
  // N on each axis the sum may stray from `net` across `unbalanced_along`: a pair a few degrees
  // off facing each other keeps its squeeze.
  double across_n = 0.0;
  // With this > 0 the sum is balanced along `unbalanced_along` too, within what friction gives
  // there: a push within asin(level_sine) of level (perpendicular to it) carries its own part
  // along it; a steeper one this coefficient times the push and the sine of its angle to it.
  double along_friction = 0.0;
  double level_sine = 0.0;
};
ForcePlan PlanBoundedForces(const std::vector<Eigen::Vector3d>& contacts,
                            const std::vector<bool>& grip, const Eigen::Vector3d& aim,
                            double nominal_n, double minimum_n, double maximum_n,
                            const Eigen::Vector3d& net, double balance_weight = 1e4,
                            const Eigen::Vector3d& unbalanced_along = Eigen::Vector3d::Zero(),
                            const FrictionShare& share = {});

// The same plan along given force directions (unit, into the object; one per contact, used where
// `grip` and not zero); `centroid` is reported as the plan's centre.
ForcePlan PlanBoundedForcesAlong(const std::vector<Eigen::Vector3d>& directions,
                                 const std::vector<bool>& grip, const Eigen::Vector3d& centroid,
                                 double nominal_n, double minimum_n, double maximum_n,
                                 const Eigen::Vector3d& net, double balance_weight = 1e4,
                                 const Eigen::Vector3d& unbalanced_along = Eigen::Vector3d::Zero(),
                                 const FrictionShare& share = {});

// Each grip contact's direction toward `aim`, kept within `max_off_normal_rad` of its own normal
// (unit, into the object): a tip pushes within its friction cone or slides. On a sphere the
// normals meet at the centre and nothing is clamped; on an elongated object the least-squares
// meeting point of a pinch across its side and a push on its cap lies outside it, behind one
// of the contacts, and that contact pushes along its normal instead of pulling (an aim behind a
// contact's tangent plane: along its normal; off by less: on the cone's edge toward the aim).
// Contacts without a normal (zero) keep the direction toward `aim`.
std::vector<Eigen::Vector3d> AimWithinCones(const std::vector<Eigen::Vector3d>& contacts,
                                            const std::vector<Eigen::Vector3d>& normals,
                                            const std::vector<bool>& grip,
                                            const Eigen::Vector3d& aim, double max_off_normal_rad);

}  // namespace dmpl
