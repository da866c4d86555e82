#include "supervisor/link_clearance.h"

#include <algorithm>

namespace dmpl {

namespace {
// Nearer the centre than this a point's direction says nothing (no link gets there anyway).
constexpr double kNearCentreM = 1e-3;
// A face seen this obliquely from the centre (its normal near 90 deg off the direction) is
// taken at this cosine: the plane's distance would vanish.
constexpr double kMinCosine = 0.1;
}  // namespace

std::optional<double> SurfaceClearance(const LinkSolid& solid, const SurfaceModel& surface,
                                       const Eigen::Isometry3d& object, double extend_m) {
  const Eigen::Isometry3d to_object = object.inverse();
  std::optional<double> least;
  for (const Eigen::Vector3d& point : solid.points) {
    const Eigen::Vector3d p = to_object * point;
    const double r = p.norm();
    if (r < kNearCentreM) continue;
    const Eigen::Vector3d d = p / r;
    const SurfacePoint s = surface.Along(d);
    std::optional<double> outside;
    if (s.known) {
      outside = (r - s.distance_m) * std::max(d.dot(s.normal), kMinCosine);
    } else if (extend_m > 0) {
      outside = surface.OutsidePlanes(p, extend_m);
    }
    if (!outside) continue;
    const double gap = *outside - solid.radius;
    least = least ? std::min(*least, gap) : gap;
  }
  return least;
}

}  // namespace dmpl
