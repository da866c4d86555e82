#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "supervisor/edge_detector.h"

namespace dmpl {
namespace {

constexpr double kTick = 0.01;      // the supervisor's period
constexpr double kTipRadius = 0.012;

// A fingertip (a sphere) slid at `speed` along a face toward an edge where the next face turns
// by `turn` (90 deg for a cube, 60 deg for a hexagonal prism: interior 120 deg), over it, and on
// along the next face: the contact point and the outward normal each tick. Before the edge the
// face is the plane y = 0 (normal +y), travel along -x toward the edge at the origin; past it
// the face is the plane through the origin turned by `turn` about z.
struct Contact {
  Eigen::Vector3d point, normal;
};
std::vector<Contact> SlideOverEdge(double turn, double speed, double before_m, double after_m) {
  std::vector<Contact> trace;
  const Eigen::Vector3d n1 = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d n2 = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()) * n1;
  const Eigen::Vector3d along2 = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()) *
                                 -Eigen::Vector3d::UnitX();
  // The tip's centre: along the first face at kTipRadius above it, round the edge on a circle
  // of kTipRadius (the contact stays on the edge), then along the second face.
  const double arc = kTipRadius * turn;
  for (double s = -before_m; s < arc + after_m; s += speed * kTick) {
    if (s < 0) {
      trace.push_back({Eigen::Vector3d(-s, 0, 0), n1});
    } else if (s < arc) {
      const double a = s / kTipRadius;
      trace.push_back({Eigen::Vector3d::Zero(),
                       Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * n1});
    } else {
      trace.push_back({(s - arc) * along2, n2});
    }
  }
  return trace;
}

TEST(EdgeDetectorTest, ACubesAndAHexagonalPrismsEdgesAreFoundAsTheTipRollsOverThem) {
  for (const double turn : {M_PI / 2, M_PI / 3}) {
    SCOPED_TRACE("turn " + std::to_string(turn));
    EdgeDetector detector;
    const auto trace = SlideOverEdge(turn, 0.02, 0.02, 0.02);
    std::vector<std::pair<int, Edge>> edges;
    for (size_t k = 0; k < trace.size(); ++k) {
      if (auto e = detector.Add(k * kTick, trace[k].point, trace[k].normal)) {
        if (e->continues) {
          ASSERT_FALSE(edges.empty());
          edges.back().second = *e;  // the same edge, turned further
        } else {
          edges.emplace_back(static_cast<int>(k), *e);
        }
      }
    }
    ASSERT_EQ(edges.size(), 1u);
    const Edge& e = edges[0].second;
    // Found while the tip rolls round the edge: the roll takes turn * r / speed (0.94 s for
    // 90 deg at 2 cm/s); the normal has turned min_turn (0.5 rad) 0.3 s after it began, found
    // then, 3 ticks either way.
    const int begins = static_cast<int>(std::round(0.02 / 0.02 / kTick));
    const int found_at = begins + static_cast<int>(std::ceil(0.5 * kTipRadius / 0.02 / kTick));
    EXPECT_NEAR(edges[0].first, found_at, 3);
    EXPECT_LT(e.point.norm(), 0.002);  // on the edge
    EXPECT_NEAR(e.normal_before.y(), 1.0, 1e-9);
    // Once the tip is round, the edge's angle is the faces' (the normal turned by it).
    EXPECT_NEAR(e.angle_rad, turn, 1e-9);
  }
}

TEST(EdgeDetectorTest, NoEdgeOnASphereSeenThroughAHalfCentimetreNoisyPose) {
  // A tip sliding round a 2.5 cm sphere (the smallest the benchmarks hold, r 1.5 cm, too) at
  // 2 cm/s for 4 s; its contacts put into the object frame with a pose estimate whose position
  // carries 5 mm of noise, low-passed as the controller does (0.1 s).
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  for (const double radius : {0.015, 0.025}) {
    EdgeDetector detector;
    Eigen::Vector3d estimate_error = Eigen::Vector3d::Zero();
    int edges = 0;
    for (int k = 0; k < 400; ++k) {
      const double a = 0.02 * k * kTick / radius;
      const Eigen::Vector3d normal(std::cos(a), std::sin(a), 0.0);
      for (int i = 0; i < 10; ++i) {  // 1 ms ticks of the controller's low-pass
        const Eigen::Vector3d raw(noise(rng), noise(rng), noise(rng));
        estimate_error += 0.001 / (0.1 + 0.001) * (raw - estimate_error);
      }
      edges += detector.Add(k * kTick, radius * normal - estimate_error, normal).has_value();
    }
    EXPECT_EQ(edges, 0) << "radius " << radius;
  }
}

TEST(EdgeDetectorTest, ALostContactStartsANewTrace) {
  EdgeDetector detector;
  detector.Add(0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  detector.Reset();
  // The same finger lands again on another face nearby: not an edge it felt.
  EXPECT_FALSE(detector.Add(0.01, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()));
}

}  // namespace
}  // namespace dmpl
