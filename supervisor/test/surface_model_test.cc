#include "supervisor/surface_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

namespace dmpl {
namespace {

// A convex shape about its centre: where a ray from the centre leaves it, and the outward
// normal there.
struct Shape {
  const char* name;
  std::function<double(const Eigen::Vector3d&)> distance;  // along a unit direction
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> normal;  // at a surface point
};

Shape Ellipsoid(const char* name, double a, double b, double c) {
  const Eigen::Vector3d r(a, b, c);
  return {name,
          [r](const Eigen::Vector3d& u) { return 1.0 / u.cwiseQuotient(r).norm(); },
          [r](const Eigen::Vector3d& p) {
            return p.cwiseQuotient(r.cwiseProduct(r)).normalized().eval();
          }};
}

Shape Cylinder(double radius, double half_length) {  // along z, flat ends
  return {"cylinder r 2 cm, 8 cm long",
          [=](const Eigen::Vector3d& u) {
            const double side = std::hypot(u.x(), u.y()) > 0 ? radius / std::hypot(u.x(), u.y())
                                                             : INFINITY;
            const double end = std::abs(u.z()) > 0 ? half_length / std::abs(u.z()) : INFINITY;
            return std::min(side, end);
          },
          [=](const Eigen::Vector3d& p) {
            if (std::abs(std::abs(p.z()) - half_length) < 1e-9) {
              return Eigen::Vector3d(0, 0, p.z() > 0 ? 1 : -1);
            }
            return Eigen::Vector3d(p.x(), p.y(), 0).normalized().eval();
          }};
}

Eigen::Vector3d RandomDirection(std::mt19937* rng) {
  std::normal_distribution<double> n(0, 1);
  return Eigen::Vector3d(n(*rng), n(*rng), n(*rng)).normalized();
}

// 300 contacts at random places on the shape, each taken with an object pose estimate 0.5 cm
// off (per axis, as the paper's noise); then the surface along 300 other random directions,
// where the model says it knows it. Returns the median and 90th percentile of the distance
// error, and of the normal's angle error.
struct Errors {
  double median_m, p90_m, median_normal_rad, known_fraction, sigma_median_m;
};

Errors Measure(const Shape& shape, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.005);
  const Eigen::Isometry3d truth =
      Eigen::Translation3d(0.07, 0.0, 0.02) * Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized());
  SurfaceModel model;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d u = RandomDirection(&rng);
    const Eigen::Vector3d p = shape.distance(u) * u;
    const Eigen::Vector3d n = shape.normal(p);
    Eigen::Isometry3d estimate = truth;
    estimate.translation() += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    model.Add(estimate, truth * p, truth.linear() * n, 0.001 * i);
  }
  std::vector<double> errors, angles, sigmas;
  int known = 0;
  const int queries = 300;
  for (int i = 0; i < queries; ++i) {
    const Eigen::Vector3d d = RandomDirection(&rng);
    const SurfacePoint s = model.Along(d);
    if (!s.known) continue;
    ++known;
    const double t = shape.distance(d);
    errors.push_back(std::abs(s.distance_m - t));
    angles.push_back(std::acos(std::clamp(s.normal.dot(shape.normal(t * d)), -1.0, 1.0)));
    sigmas.push_back(s.sigma_m);
  }
  auto quantile = [](std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<size_t>(q * (v.size() - 1))];
  };
  return {quantile(errors, 0.5), quantile(errors, 0.9), quantile(angles, 0.5),
          static_cast<double>(known) / queries, quantile(sigmas, 0.5)};
}

TEST(SurfaceModelTest, LearnsSpheresCylindersAndEllipsoidsUnderPoseNoise) {
  // Bounds from seeds 1-5 (median of the distance error at most 1.9 mm on every shape; 90th
  // percentile at most 3.0 mm on the smooth ones), with a margin. A single contact is 5 mm off
  // per axis; the kernel averages a few tens of them. The cylinder's rim mixes the planes of a
  // side and an end: its tail is the edge that issue 29's faces and edges are for.
  struct Case {
    Shape shape;
    double median_m, p90_m, known;
  };
  const std::vector<Case> cases = {
      {Ellipsoid("sphere r 2.5 cm", 0.025, 0.025, 0.025), 0.0025, 0.004, 0.95},
      {Cylinder(0.02, 0.04), 0.0025, 0.012, 0.85},
      {Ellipsoid("ellipsoid 3.5 x 2.5 x 2 cm", 0.035, 0.025, 0.02), 0.0025, 0.004, 0.95}};
  for (const Case& c : cases) {
    const Errors e = Measure(c.shape, 1);
    std::printf("%-28s distance error median %.2f mm, 90%% %.2f mm (sigma said %.2f mm); normal "
                "%.1f deg; known in %.0f%% of directions\n",
                c.shape.name, e.median_m * 1e3, e.p90_m * 1e3, e.sigma_median_m * 1e3,
                e.median_normal_rad * 180 / M_PI, 100 * e.known_fraction);
    EXPECT_LT(e.median_m, c.median_m) << c.shape.name;
    EXPECT_LT(e.p90_m, c.p90_m) << c.shape.name;
    EXPECT_LT(e.median_normal_rad, 0.15) << c.shape.name;
    EXPECT_GT(e.known_fraction, c.known) << c.shape.name;
  }
}

TEST(SurfaceModelTest, AnUnexploredSideIsUnknownAndASlidingFingerIsThinnedOut) {
  SurfaceModel model;
  // One finger slides 2 cm along the +y side of a sphere, 0.1 mm per tick: 200 readings.
  for (int i = 0; i < 200; ++i) {
    const double a = -0.4 + 0.8 * i / 199.0;
    const Eigen::Vector3d n(std::sin(a), std::cos(a), 0);
    model.Add(Eigen::Isometry3d::Identity(), 0.025 * n, n, 0.001 * i);
  }
  EXPECT_LT(model.size(), 20u);  // one per 2 mm
  const SurfacePoint here = model.Along(Eigen::Vector3d::UnitY());
  EXPECT_TRUE(here.known);
  EXPECT_NEAR(here.distance_m, 0.025, 1e-3);
  EXPECT_FALSE(model.Along(-Eigen::Vector3d::UnitY()).known);
  EXPECT_FALSE(model.Along(Eigen::Vector3d::UnitZ()).known);
}

}  // namespace
}  // namespace dmpl

namespace dmpl {
namespace {

// A standing cylinder (r 2 cm, along z) felt only around its middle (|z| < 1 cm), under the
// paper's 0.5 cm pose noise: 3 cm up its side, where no direction from the centre is known,
// the felt side's planes still say how far out a point stands.
TEST(SurfaceModelTest, TheFeltSidesPlanesExtendPastWhereItWasFelt) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.005);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), height(-0.01, 0.01);
  SurfaceModel model;
  for (int i = 0; i < 400; ++i) {
    const double a = angle(rng);
    const Eigen::Vector3d n(std::cos(a), std::sin(a), 0.0);
    Eigen::Isometry3d estimate = Eigen::Isometry3d::Identity();
    estimate.translation() = Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    model.Add(estimate, 0.02 * n + Eigen::Vector3d(0, 0, height(rng)), n, 0.001 * i);
  }
  const Eigen::Vector3d side(std::cos(0.3), std::sin(0.3), 0.0);
  for (double out : {-0.005, 0.0, 0.005}) {
    const Eigen::Vector3d p = (0.02 + out) * side + Eigen::Vector3d(0, 0, 0.03);
    EXPECT_FALSE(model.Along(p).known);
    const std::optional<double> d = model.OutsidePlanes(p, 0.015);
    ASSERT_TRUE(d.has_value());
    // The planes' offsets average the pose noise over the few tens near the point: 1.5 mm.
    EXPECT_NEAR(*d, out, 0.0015);
  }
  // Far from every contact the planes say nothing.
  EXPECT_FALSE(model.OutsidePlanes(Eigen::Vector3d(0, 0, 0.2), 0.015).has_value());
}

}  // namespace
}  // namespace dmpl
