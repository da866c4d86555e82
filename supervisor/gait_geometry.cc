#include "supervisor/gait_geometry.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace dmpl {

namespace {

// An orthonormal basis (u, v) of the plane normal to `axis` (unit).
void PlaneBasis(const Eigen::Vector3d& axis, Eigen::Vector3d* u, Eigen::Vector3d* v) {
  *u = axis.unitOrthogonal();
  *v = axis.cross(*u);
}
double AngleAbout(const Eigen::Vector3d& p, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(p.dot(v), p.dot(u));
}
double Radial(const Eigen::Vector3d& p, const Eigen::Vector3d& axis) {
  return (p - p.dot(axis) * axis).norm();
}
double WrapPi(double a) { return std::remainder(a, 2.0 * M_PI); }
// The angle two fingertips `clearance` apart need at `radius` from the axis.
double GapAngle(double clearance, double radius) {
  return radius <= 0 ? M_PI : 2.0 * std::asin(std::min(1.0, clearance / (2.0 * radius)));
}

}  // namespace

GaitGeometry::GaitGeometry(std::vector<Eigen::Vector3d> home, const Eigen::Vector3d& home_centre,
                           const GaitSpec& spec, double max_deviation_rad)
    : home_(std::move(home)),
      home_centre_(home_centre),
      tip_clearance_m_(spec.tip_clearance_m),
      overlap_about_(spec.overlap_about[0], spec.overlap_about[1], spec.overlap_about[2]),
      overlap_max_tilt_rad_(spec.overlap_max_tilt_rad),
      max_deviation_rad_(max_deviation_rad) {}

bool GaitGeometry::AroundFingers(const Eigen::Vector3d& axis) const {
  return std::abs(axis.normalized().dot(overlap_about_.normalized())) >=
         std::cos(overlap_max_tilt_rad_);
}

double GaitGeometry::StepLimit(const Eigen::Vector3d& axis_in, const ControllerView& view,
                               double smallest) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  const int n = num_fingers();
  // Only for fingers that stand around the axis (their homes at distinct angles about it).
  Eigen::Vector3d u, v;
  PlaneBasis(axis, &u, &v);
  std::vector<double> angles;
  for (int k = 0; k < n; ++k) angles.push_back(AngleAbout(home_[k] - home_centre_, u, v));
  std::sort(angles.begin(), angles.end());
  for (int k = 1; k < n; ++k) {
    if (!(angles[k] - angles[k - 1] > 1e-6)) return 0.0;
  }
  // How far the fingertips stand from the axis now (the closest one: an elongated section
  // brings some closer).
  const Eigen::Vector3d centre = view.object.translation();
  double radius = 0.0;
  bool any = false;
  for (int k = 0; k < n; ++k) {
    if (!view.fingers[k].in_contact) continue;
    const double r = Radial(view.fingers[k].tip - centre, axis);
    radius = any ? std::min(radius, r) : r;
    any = true;
  }
  if (!any || !(radius > 0)) return 0.0;
  // The fingers stand around the axis 2 pi / n apart on average (a grasp that left two closer
  // leaves two further apart, and KeepClear keeps an explorer off the closer one).
  const double spacing = 2.0 * M_PI / static_cast<double>(n);
  const double limit =
      (spacing - GapAngle(tip_clearance_m_, radius)) / static_cast<double>(n - 1);
  // Too small an object to gait at all with these fingers: the smallest steps still try.
  return std::max(limit, smallest);
}

namespace {
// Homes within this of the level through the centre: the fingers stand around the vertical.
constexpr double kLevelHomeRad = 0.35;

// `v` turned toward `toward` by at most `most_rad` (all the way when it is nearer); unchanged
// when either is zero or they are parallel or opposed (no plane to turn in).
Eigen::Vector3d TurnedToward(const Eigen::Vector3d& v, const Eigen::Vector3d& toward,
                             double most_rad) {
  const Eigen::Vector3d about = v.cross(toward);
  if (toward.norm() < 1e-6 || about.norm() < 1e-12) return v;
  const double angle = std::atan2(about.norm(), v.dot(toward));
  return Eigen::AngleAxisd(std::min(angle, most_rad), about.normalized()) * v;
}
}  // namespace

Eigen::Vector3d BelowElevation(const Eigen::Vector3d& offset, const Eigen::Vector3d& up,
                               double max_elevation_rad) {
  const double r = offset.norm();
  const Eigen::Vector3d level = offset - offset.dot(up) * up;
  if (r < 1e-12 || level.norm() < 1e-9 * r) return offset;
  const double elevation = std::asin(std::clamp(offset.dot(up) / r, -1.0, 1.0));
  if (elevation <= max_elevation_rad) return offset;
  const double lowered = std::max(max_elevation_rad, -M_PI / 2);
  return r * (std::cos(lowered) * level.normalized() + std::sin(lowered) * up);
}

Eigen::Vector3d GaitGeometry::ExplorePoint(int f, const Eigen::AngleAxisd& turn,
                                           const ControllerView& view,
                                           const SurfaceModel& surface, double tip_radius_m,
                                           double max_elevation_rad,
                                           double face_partner_rad) const {
  const Eigen::Vector3d centre = view.object.translation();
  Eigen::Vector3d offset = turn * (home_[f] - home_centre_);
  if (max_elevation_rad < M_PI / 2 && PalmBelow(view.gravity) && HomesLevel(view.gravity)) {
    offset = BelowElevation(offset, -view.gravity.normalized(), max_elevation_rad);
  }
  const int partner = face_partner_rad > 0 ? Partner(f) : -1;
  if (partner >= 0 && view.fingers[partner].in_contact) {
    // Toward the antipode of the partner's contact, through the centre.
    offset = TurnedToward(offset, centre - view.fingers[partner].contact, face_partner_rad);
  }
  const Eigen::Vector3d guess = centre + offset;
  if (tip_radius_m <= 0) return guess;
  const Eigen::Matrix3d to_palm = view.object.linear();
  const SurfacePoint s = surface.Along(to_palm.transpose() * (guess - centre));
  // The model only moves the explorer where it knows the surface lies elsewhere.
  if (!s.Differs((guess - centre).norm() - tip_radius_m)) return guess;
  return centre + to_palm * (s.point + tip_radius_m * s.normal);
}

int GaitGeometry::Partner(int f) const {
  const Eigen::Vector3d own = (home_[f] - home_centre_).normalized();
  int partner = -1;
  double least = -0.5;
  for (int k = 0; k < num_fingers(); ++k) {
    const double c = own.dot((home_[k] - home_centre_).normalized());
    if (k != f && c < least) {
      least = c;
      partner = k;
    }
  }
  return partner;
}

bool GaitGeometry::HomesLevel(const Eigen::Vector3d& gravity) const {
  if (gravity.norm() < 0.5) return false;
  const Eigen::Vector3d up = -gravity.normalized();
  for (const Eigen::Vector3d& home : home_) {
    const Eigen::Vector3d offset = home - home_centre_;
    if (offset.norm() < 1e-9) return false;
    if (std::abs(offset.normalized().dot(up)) > std::sin(kLevelHomeRad)) return false;
  }
  return true;
}

bool GaitGeometry::PalmBelow(const Eigen::Vector3d& gravity, double min_cos) {
  return gravity.norm() > 0.5 && gravity.normalized().x() < -min_cos;
}

Eigen::Vector3d GaitGeometry::TowardTipFront(int f, const Eigen::Vector3d& point,
                                             const ControllerView& view,
                                             const SurfaceModel& surface, double tip_radius_m,
                                             double max_angle, double most) const {
  const Eigen::Vector3d centre = view.object.translation();
  const Eigen::Matrix3d to_palm = view.object.linear();
  const Eigen::Vector3d& axis = view.fingers[f].tip_axis;
  const Eigen::Vector3d d = (point - centre).normalized();
  // Toward the base: minus the tip's axis, across the direction from the centre.
  const Eigen::Vector3d back = -axis + axis.dot(d) * d;
  if (back.norm() < 1e-6 || tip_radius_m <= 0) return point;
  const Eigen::Vector3d about = d.cross(back).normalized();
  constexpr double kStep = 0.05;
  Eigen::Vector3d best = point;
  double best_angle = M_PI;
  for (double a = 0.0; a <= most + 1e-9; a += kStep) {
    const Eigen::Vector3d dir = Eigen::AngleAxisd(a, about) * d;
    const SurfacePoint s = surface.Along(to_palm.transpose() * dir);
    // Unfelt surface: as far as the point, facing out from the centre.
    const Eigen::Vector3d normal = s.known ? Eigen::Vector3d(to_palm * s.normal) : dir;
    const double distance = s.known ? s.distance_m : (point - centre).norm() - tip_radius_m;
    const double angle = std::acos(std::clamp(-normal.dot(axis), -1.0, 1.0));
    const Eigen::Vector3d candidate = centre + distance * dir + tip_radius_m * normal;
    if (angle <= max_angle) return a == 0.0 ? point : candidate;
    if (angle < best_angle) {
      best_angle = angle;
      best = candidate;
    }
  }
  return best;
}

double GaitGeometry::LimitBack(int f, const Eigen::Vector3d& axis, double back) const {
  const Eigen::Vector3d home = (home_[f] - home_centre_).normalized();
  const double sin_beta = axis.normalized().cross(home).norm();
  const double d = max_deviation_rad_;
  const double most =
      sin_beta <= std::sin(d / 2) ? M_PI : 2.0 * std::asin(std::sin(d / 2) / sin_beta);
  return std::copysign(std::min(std::abs(back), most), back);
}

Eigen::Vector3d GaitGeometry::KeepClear(int explorer, const Eigen::Vector3d& axis_in, double sign,
                                        double step, bool neighbour_rides,
                                        const Eigen::Vector3d& target,
                                        const ControllerView& view) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  Eigen::Vector3d u, v;
  PlaneBasis(axis, &u, &v);
  const Eigen::Vector3d centre = view.object.translation();
  const double own = AngleAbout(view.fingers[explorer].tip - centre, u, v);
  // The finger the explorer slides back toward: the nearest one behind it.
  int neighbour = -1;
  double nearest = 2.0 * M_PI;
  for (int k = 0; k < num_fingers(); ++k) {
    if (k == explorer) continue;
    double behind = sign * (own - AngleAbout(view.fingers[k].tip - centre, u, v));
    behind = std::fmod(behind + 4.0 * M_PI, 2.0 * M_PI);
    if (behind < nearest) {
      nearest = behind;
      neighbour = k;
    }
  }
  if (neighbour < 0) return target;
  const Eigen::Vector3d other = view.fingers[neighbour].tip - centre;
  const double other_end = AngleAbout(other, u, v) + (neighbour_rides ? sign * step : 0.0);
  const Eigen::Vector3d offset = target - centre;
  const double ahead = WrapPi(sign * (AngleAbout(offset, u, v) - other_end));
  const double gap =
      GapAngle(tip_clearance_m_, std::min(Radial(offset, axis), Radial(other, axis)));
  if (ahead >= gap) return target;
  return centre + Eigen::AngleAxisd(sign * (gap - ahead), axis) * offset;
}

double GaitGeometry::Deviation(int k, const Eigen::AngleAxisd& turn,
                               const ControllerView& view) const {
  const Eigen::Vector3d home = home_[k] - home_centre_;
  const Eigen::Vector3d now = turn * (view.fingers[k].tip - view.object.translation());
  const double c = home.dot(now) / (home.norm() * now.norm());
  return std::acos(std::clamp(c, -1.0, 1.0));
}

double GaitGeometry::StepWithinReach(const Eigen::Vector3d& axis_in, double step, int skip,
                                     const ControllerView& view) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  // Each riding finger's bound: the limit, or where it stands if it is already beyond.
  std::vector<double> bound(num_fingers(), 0.0);
  for (int k = 0; k < num_fingers(); ++k) {
    bound[k] = std::max(max_deviation_rad_, Deviation(k, Eigen::AngleAxisd(0.0, axis), view));
  }
  constexpr int kSamples = 16;
  double allowed = 0.0;
  for (int i = 1; i <= kSamples; ++i) {
    const double phi = step * i / kSamples;
    for (int k = 0; k < num_fingers(); ++k) {
      if (k == skip || !view.fingers[k].in_contact) continue;
      if (Deviation(k, Eigen::AngleAxisd(phi, axis), view) > bound[k]) return allowed;
    }
    allowed = phi;
  }
  return allowed;
}

int GaitGeometry::FurthestFromHome(const Eigen::Vector3d& axis, double step, int skip,
                                   const ControllerView& view) const {
  int furthest = -1;
  double most = -1.0;
  for (int k = 0; k < num_fingers(); ++k) {
    if (k == skip) continue;
    const double d = Deviation(k, Eigen::AngleAxisd(step, axis.normalized()), view);
    if (d > most) {
      most = d;
      furthest = k;
    }
  }
  return furthest;
}

}  // namespace dmpl
