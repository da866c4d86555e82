#pragma once
// For the supervisor's tests: a sphere the fingertips have felt all round, and the grasp the gait
// holds it in.
#include <cmath>

#include <Eigen/Geometry>

#include "supervisor/surface_model.h"

namespace dmpl::testing {

// fig10_gait_sphere at 2 s: the object's centre, each tip's centre (T below, F and R at the
// sides, M above) and its axis as the controller reported them.
inline const Eigen::Vector3d kGaitCentre(0.071, 0.002, 0.018);
inline const Eigen::Vector3d kGaitTips[] = {{0.0715, 0.0163, -0.0162},
                                            {0.0705, 0.0376, 0.0323},
                                            {0.0698, 0.0041, 0.0554},
                                            {0.0708, -0.0336, 0.0194}};
inline const Eigen::Vector3d kGaitTipAxes[] = {{0.024, -0.730, 0.683}, {0.319, -0.122, -0.940},
                                               {0.643, 0.038, -0.765}, {0.148, 0.110, -0.983}};

// `count` contacts all over a sphere of `radius` about the object's centre (a Fibonacci
// lattice), or only where x > `min_x` (of the radius) in the object's frame, each felt 1 ms after
// the last, with the object at `object`.
inline SurfaceModel FeltSphere(const Eigen::Isometry3d& object, double radius, int count,
                               double min_x = -1.0) {
  SurfaceModel model;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - z * z);
    const double phi = i * M_PI * (3.0 - std::sqrt(5.0));
    const Eigen::Vector3d d(r * std::cos(phi), r * std::sin(phi), z);
    if (d.x() <= min_x) continue;
    model.Add(object, object * (radius * d), object.linear() * d, 0.001 * i);
  }
  return model;
}

}  // namespace dmpl::testing
