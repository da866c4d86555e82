#pragma once
// How far a finger's link stands off the object as touch has taught its surface: the check a
// placement needs so that a finger meets the object with its tip, not its links (issue 28).
// Pure: the links from the hand's kinematics (finger_links.h), the surface from the fingertips'
// contacts (surface_model.h); nothing of the object's true shape.
#include <optional>

#include <Eigen/Geometry>

#include "components/kinematics/finger_links.h"
#include "supervisor/surface_model.h"

namespace dmpl {

// The clearance of `solid` (palm frame) from the felt surface, m (negative: it reaches into
// the object by that much), with `object` the object's pose estimate: of each of its points, the
// distance from the surface in the point's direction from the centre, measured along the
// surface's normal there (exact for a face, and for a sphere about its centre), less the solid's
// radius; the least of them. Only points in directions the model knows count; nothing when it
// knows none of them.
// With `extend_m` > 0, a point in a direction the model does not know is measured against the
// felt tangent planes near it instead (SurfaceModel::OutsidePlanes, of that width).
std::optional<double> SurfaceClearance(const LinkSolid& solid, const SurfaceModel& surface,
                                       const Eigen::Isometry3d& object, double extend_m = 0.0);

}  // namespace dmpl
