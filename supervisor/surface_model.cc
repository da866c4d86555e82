#include "supervisor/surface_model.h"

#include <algorithm>
#include <cmath>

namespace dmpl {

namespace {
constexpr double kMinFacing = 0.7;  // cos 45 deg
}  // namespace

void SurfaceModel::Add(const Eigen::Isometry3d& object, const Eigen::Vector3d& point,
                       const Eigen::Vector3d& outward, double time_s) {
  const Eigen::Vector3d p = object.inverse() * point;
  const Eigen::Vector3d n = (object.linear().transpose() * outward).normalized();
  if (!p.allFinite() || !n.allFinite() || p.norm() < 1e-6) return;
  // A sliding finger reports a contact every tick: keep one per few millimetres (the one kept
  // is seen again now).
  for (SurfaceContact& c : contacts_) {
    if ((c.point - p).norm() < params_.min_spacing_m) {
      c.time_s = time_s;
      return;
    }
  }
  if (contacts_.size() >= params_.max_contacts) contacts_.erase(contacts_.begin());
  contacts_.push_back({p, n, p.normalized(), time_s});
}

SurfacePoint SurfaceModel::Along(const Eigen::Vector3d& direction) const {
  const Eigen::Vector3d d = direction.normalized();
  const double inv_width2 = 1.0 / (params_.kernel_rad * params_.kernel_rad);
  double sum_w = 0.0, sum_w2 = 0.0, sum_t = 0.0, sum_t2 = 0.0;
  Eigen::Vector3d sum_n = Eigen::Vector3d::Zero();
  for (const SurfaceContact& c : contacts_) {
    const double facing = c.normal.dot(d);
    if (facing < kMinFacing) continue;  // a plane seen edge-on (or from behind) says little
    const double w = std::exp((c.direction.dot(d) - 1.0) * inv_width2);
    // Where the contact's tangent plane meets the ray (too far on a convex curve: 1 / cos of
    // the angle between them) and how far along the ray the contact itself lies (too near: cos):
    // their geometric mean is exact on a sphere and on a face seen head-on.
    const double on_plane = c.normal.dot(c.point) / facing;
    const double t = std::sqrt(std::max(0.0, c.point.dot(d)) * on_plane);
    sum_w += w;
    sum_w2 += w * w;
    sum_t += w * t;
    sum_t2 += w * t * t;
    sum_n += w * c.normal;
  }
  SurfacePoint s;
  s.support = sum_w;
  if (!(sum_w > 0)) return s;
  s.distance_m = sum_t / sum_w;
  s.point = s.distance_m * d;
  s.normal = sum_n.normalized();
  // The standard error of the mean over the effective number of contacts behind it: from the
  // planes' spread, or at least the pose noise (a few contacts say little of their spread).
  const double spread2 = std::max(sum_t2 / sum_w - s.distance_m * s.distance_m,
                                  params_.pose_sigma_m * params_.pose_sigma_m);
  s.sigma_m = std::sqrt(spread2 * sum_w2 / (sum_w * sum_w));
  s.known = sum_w >= params_.min_support;
  return s;
}

std::optional<double> SurfaceModel::OutsidePlanes(const Eigen::Vector3d& point,
                                                  double width_m) const {
  const double inv_width2 = 1.0 / (2.0 * width_m * width_m);
  // The surface's normal near the point: the nearby contacts' mean. Only planes facing that way
  // say where it lies (on a curved surface a plane from round the curve has the point inside).
  Eigen::Vector3d mean_normal = Eigen::Vector3d::Zero();
  for (const SurfaceContact& c : contacts_) {
    mean_normal += std::exp(-(c.point - point).squaredNorm() * inv_width2) * c.normal;
  }
  if (mean_normal.norm() < 1e-9) return std::nullopt;
  mean_normal.normalize();
  const double inv_kernel2 = 1.0 / (params_.kernel_rad * params_.kernel_rad);
  double sum_w = 0.0, sum_d = 0.0;
  for (const SurfaceContact& c : contacts_) {
    const double w = std::exp(-(c.point - point).squaredNorm() * inv_width2 +
                              (c.normal.dot(mean_normal) - 1.0) * inv_kernel2);
    sum_w += w;
    sum_d += w * c.normal.dot(point - c.point);
  }
  if (!(sum_w >= params_.min_support)) return std::nullopt;
  return sum_d / sum_w;
}

}  // namespace dmpl
