#include "supervisor/face_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmpl {

namespace {

// The felt tangent plane the tip's centre `tip` lies furthest outside of: the face a tip there
// meets first (on a convex object the felt planes bound it from outside).
const SurfaceContact* FacingContact(const Eigen::Vector3d& tip, const SurfaceModel& surface) {
  const SurfaceContact* facing = nullptr;
  double most = -std::numeric_limits<double>::infinity();
  for (const SurfaceContact& c : surface.contacts()) {
    const double outside = c.normal.dot(tip - c.point);
    if (outside > most) {
      most = outside;
      facing = &c;
    }
  }
  return facing;
}

// Whether the face of the felt contact `facing` is one of the faces felt flat: its normal within
// the detector's tolerance, its plane within a few millimetres (the pose estimate's drift).
bool FeltFlat(const SurfaceContact& facing, const std::vector<FlatFace>& flat) {
  constexpr double kSamePlaneM = 0.004;
  const double same = std::cos(FlatFaceDetector::kToleranceRad);
  return std::any_of(flat.begin(), flat.end(), [&](const FlatFace& face) {
    return face.normal.dot(facing.normal) >= same &&
           std::abs(face.normal.dot(facing.point - face.point)) <= kSamePlaneM;
  });
}

// Whether `point`, on the plane of a face with normal `normal`, lies outside a felt tangent plane
// turned kPastEdgeRad or more from it (by more than kPastEdgeM): past the face's end, on the way
// round to another face (a hexagonal prism's next side, 1.05 rad on, or a plane felt on an edge).
// On a convex object every point of the face itself lies inside every felt plane.
bool PastAnEdge(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                const SurfaceModel& surface) {
  constexpr double kPastEdgeRad = 0.35;  // past the tip geometry's error in a normal
  constexpr double kPastEdgeM = 0.0005;
  const double turned = std::cos(kPastEdgeRad);
  return std::any_of(surface.contacts().begin(), surface.contacts().end(),
                     [&](const SurfaceContact& c) {
                       return c.normal.dot(normal) <= turned &&
                              c.normal.dot(point - c.point) > kPastEdgeM;
                     });
}

}  // namespace

std::optional<FlatFace> FlatFaceDetector::Add(double time_s, const Eigen::Vector3d& point,
                                              const Eigen::Vector3d& normal) {
  if (!start_ || start_->normal.dot(normal) < std::cos(kToleranceRad) ||
      time_s - start_->time_s > kWindowS) {
    start_ = Start{time_s, point, normal, false};
    return std::nullopt;
  }
  if (start_->reported || (point - start_->point).norm() < kSpanM) return std::nullopt;
  start_->reported = true;
  return FlatFace{0.5 * (start_->point + point), start_->normal};
}

bool MeetsFlatFace(const Eigen::Vector3d& tip, const SurfaceModel& surface,
                   const std::vector<FlatFace>& flat) {
  if (flat.empty()) return false;  // a curved object's case: no contact need be looked at
  const SurfaceContact* facing = FacingContact(tip, surface);
  return facing != nullptr && FeltFlat(*facing, flat);
}

Eigen::Vector3d KeepInsideFace(const Eigen::Vector3d& tip, const SurfaceModel& surface,
                               const std::vector<FlatFace>& flat, const FaceBoundsParams& params,
                               double* moved_m) {
  if (moved_m != nullptr) *moved_m = 0.0;
  if (params.margin_m <= 0) return tip;
  const SurfaceContact* facing = FacingContact(tip, surface);
  if (facing == nullptr || !FeltFlat(*facing, flat)) return tip;
  const Eigen::Vector3d n = facing->normal;
  // The contact under the tip's centre, on its face.
  const Eigen::Vector3d under = tip - n * n.dot(tip - facing->point);
  if (PastAnEdge(under, n, surface)) return tip;
  Eigen::Vector3d p = under;
  const double apart = std::cos(params.min_angle_rad);
  // Twice over the planes: a correction away from one edge may bring the point nearer another
  // (on a narrow face it ends as far from both as it can).
  for (int pass = 0; pass < 2; ++pass) {
    for (const SurfaceContact& c : surface.contacts()) {
      if (c.normal.dot(n) > apart) continue;
      // Along the face toward the plane, the plane's offset changes at `rate` per metre.
      const Eigen::Vector3d in_face = c.normal - c.normal.dot(n) * n;
      const double rate = in_face.norm();
      if (rate < 1e-6) continue;  // the opposite face: parallel to this one
      const double room = c.normal.dot(c.point - p) / rate;
      if (room < 0 || room >= params.margin_m) continue;  // (room < 0: past, after noise)
      p -= (params.margin_m - room) * in_face / rate;
    }
  }
  // The tip moved along its face as its contact was.
  if (moved_m != nullptr) *moved_m = (p - under).norm();
  return tip + (p - under);
}

}  // namespace dmpl
