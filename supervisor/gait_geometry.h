#pragma once
// The geometry of finger gaiting, as pure functions of where the fingers stood when the first
// task began (their homes), where they and the object are now (the controller's view), and the
// gait's settings. Nothing here commands anything: the Gait asks, then acts.
//
// The explorer's next point lies in the direction of its home turned about the sensed centre
// (ExplorePoint): as far from the centre as the home was, or on the surface the fingers have
// felt there (surface_model.h) where that is known to lie elsewhere.
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "supervisor/supervisor_types.h"
#include "supervisor/surface_model.h"
#include "supervisor/task_description.h"

namespace dmpl {

// `offset` (from the object's centre) turned toward the level (perpendicular to `up`, unit)
// about the horizontal axis across it, so that its elevation above the level is at most
// `max_elevation_rad`; unchanged when it is already, or when it points straight up or down.
Eigen::Vector3d BelowElevation(const Eigen::Vector3d& offset, const Eigen::Vector3d& up,
                               double max_elevation_rad);

class GaitGeometry {
 public:
  // `max_deviation_rad`: how far (seen from the object's centre) a finger may be from its home
  // (0: no limit).
  GaitGeometry(std::vector<Eigen::Vector3d> home, const Eigen::Vector3d& home_centre,
               const GaitSpec& spec, double max_deviation_rad);

  // Whether the fingers stand around `axis` (spec.overlap_about, within overlap_max_tilt_rad).
  bool AroundFingers(const Eigen::Vector3d& axis) const;
  // The largest step the fingers' spacing around `axis` allows (spec.tip_clearance_m), at least
  // `smallest`; 0 when the fingers do not stand around it. Between two explores of a finger the
  // one it slides back toward rides n - 1 steps toward it, so the fingers' spacing (2 pi / n)
  // must hold n - 1 steps and the angle two fingertips need at the distance they stand from
  // the axis.
  double StepLimit(const Eigen::Vector3d& axis, const ControllerView& view,
                   double smallest) const;
  // Where finger `f`'s tip centre goes: toward its home turned by `turn` about the sensed
  // centre, at the home's distance from the centre, unless `surface` knows the surface in that
  // direction to lie elsewhere (by more than 3 mm and twice its uncertainty): then
  // `tip_radius_m` off the felt surface.
  // With `max_elevation_rad` below pi / 2, gravity sensed (view.gravity) and the fingers
  // standing around the vertical (HomesLevel) over the palm (PalmBelow), the direction is
  // first lowered along its meridian to at most that elevation above the level through the
  // centre (BelowElevation): a push from above the object's equator pushes it along gravity,
  // and on a slick object friction cannot carry that as well as the weight. With the palm
  // sideways one finger holds from above and one from below; palm down, lowered is away from
  // the palm, where the finger wraps its links round the object: the limit does not apply in
  // either (measured: docs/benchmarks.md).
  // With `face_partner_rad` > 0 the direction is then turned toward the antipode (through the
  // sensed centre) of the partner's contact (Partner), by at most that angle: a pair that faces
  // each other squeezes the object without pushing it anywhere, and on a sphere two antipodal
  // contacts stay antipodal while they ride its turns.
  Eigen::Vector3d ExplorePoint(int f, const Eigen::AngleAxisd& turn, const ControllerView& view,
                               const SurfaceModel& surface, double tip_radius_m,
                               double max_elevation_rad = M_PI / 2,
                               double face_partner_rad = 0.0) const;
  // The finger whose home stands across the centre from finger `f`'s (the least cosine between
  // the homes' directions, below -0.5); -1 when none does.
  int Partner(int f) const;
  // The explorer `f`'s `point` (tip centre), moved along the felt surface toward the finger's
  // base (against its tip's axis) in steps of a few degrees about the centre until the surface's
  // normal there lies within `max_angle` of the tip's axis as it stands now (the point where
  // it would touch with its front, not the side next to its link); the point itself if it
  // does, or the best found within `most` rad.
  Eigen::Vector3d TowardTipFront(int f, const Eigen::Vector3d& point, const ControllerView& view,
                                 const SurfaceModel& surface, double tip_radius_m,
                                 double max_angle, double most = 0.6) const;
  // `back` (rad about `axis`), no further than the deviation allows finger `f` from its home:
  // a turn by phi about the axis moves a point at beta from it by 2 asin(sin(beta) sin(phi/2)).
  double LimitBack(int f, const Eigen::Vector3d& axis, double back) const;
  // Whether every finger's home lies within 20 deg of the level through the home centre
  // (against `gravity`, palm frame; false while it is not sensed): the palm up or down.
  bool HomesLevel(const Eigen::Vector3d& gravity) const;
  // Whether gravity (palm frame) points into the palm (along -x, the palm normal's opposite):
  // the object rests toward the palm, and what lies below its centre lies toward the palm. With
  // `min_cos` > 0, only within acos(min_cos) of pointing straight into it.
  static bool PalmBelow(const Eigen::Vector3d& gravity, double min_cos = 0.0);
  // The explorer's `target` moved forward (about `axis`, by `sign`) until it keeps the clearance
  // from the finger it slides back toward, where that finger will be after `step` (if it rides).
  Eigen::Vector3d KeepClear(int explorer, const Eigen::Vector3d& axis, double sign, double step,
                            bool neighbour_rides, const Eigen::Vector3d& target,
                            const ControllerView& view) const;
  // The angle (about the object's centre) between finger k's home and where it would be after
  // `turn`.
  double Deviation(int k, const Eigen::AngleAxisd& turn, const ControllerView& view) const;
  // The largest part of `step` about `axis` that leaves every finger that rides it (all but
  // `skip`, if any; only fingers in contact) within the deviation, or no further than it is.
  double StepWithinReach(const Eigen::Vector3d& axis, double step, int skip,
                         const ControllerView& view) const;
  // The finger (not `skip`) that `step` about `axis` takes furthest from its home.
  int FurthestFromHome(const Eigen::Vector3d& axis, double step, int skip,
                       const ControllerView& view) const;

 private:
  int num_fingers() const { return static_cast<int>(home_.size()); }

  std::vector<Eigen::Vector3d> home_;
  Eigen::Vector3d home_centre_;
  double tip_clearance_m_;
  Eigen::Vector3d overlap_about_;
  double overlap_max_tilt_rad_;
  double max_deviation_rad_;
};

}  // namespace dmpl
