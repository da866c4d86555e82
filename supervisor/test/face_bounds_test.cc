#include "supervisor/face_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace dmpl {
namespace {

constexpr double kHalf = 0.025;    // the 5 cm cube's half size
constexpr double kTip = 0.012;     // the fingertip's radius
constexpr double kMargin = 0.009;  // the distal link's half width
// What the supervisor's object estimate puts into a contact's offset along its normal: on the
// nominal sphere (r 2.5 cm, 0.5 cm camera noise, a 20-goal run) 90 % of the felt planes lie
// within 23.4-27.5 mm of the centre. Taken as a Gaussian of 1.5 mm per axis.
constexpr double kNoiseM = 0.0015;

FaceBoundsParams On() {
  FaceBoundsParams p;
  p.margin_m = kMargin;
  return p;
}

// Contacts felt at `points` (object frame) with `outward`, each with the object's position
// estimate off by the noise (the model keeps them in the estimate's frame).
void Feel(SurfaceModel* surface, const std::vector<Eigen::Vector3d>& points,
          const Eigen::Vector3d& outward, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, kNoiseM);
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d off(noise(*rng), noise(*rng), noise(*rng));
    surface->Add(Eigen::Isometry3d(Eigen::Translation3d(off)), p, outward, 0.0);
  }
}

// The cube as a four-finger grasp feels it: a dwell at the middle of -z, +z and +y (thumb,
// middle and fore finger), and on -y the ring finger slid 1.5 cm from the middle.
SurfaceModel CubeHeldAtFourFaces(uint32_t seed) {
  std::mt19937 rng(seed);
  SurfaceModel surface;
  for (const Eigen::Vector3d& n :
       {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 1, 0)}) {
    Feel(&surface, {kHalf * n}, n, &rng);
  }
  std::vector<Eigen::Vector3d> slide;
  for (int i = 0; i <= 5; ++i) slide.push_back({0.003 * i, -kHalf, 0.0});
  Feel(&surface, slide, -Eigen::Vector3d::UnitY(), &rng);
  return surface;
}

// That slide felt -y flat (FlatFaceDetector).
const std::vector<FlatFace> kMinusYFlat = {{{0.0075, -kHalf, 0.0}, -Eigen::Vector3d::UnitY()}};

// The tip's centre over the -y face, its contact at (x, z).
Eigen::Vector3d OverMinusY(double x, double z) { return {x, -kHalf - kTip, z}; }

TEST(FaceBoundsTest, APointNearAnEdgeOfTheGraspIsKeptTheMarginInsideItsFace) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const SurfaceModel surface = CubeHeldAtFourFaces(seed);
    // 5 mm from the edge with +z (felt only by the middle finger's dwell).
    double moved = 0.0;
    const Eigen::Vector3d tip = OverMinusY(0.004, 0.020);
    const Eigen::Vector3d kept = KeepInsideFace(tip, surface, kMinusYFlat, On(), &moved);
    // To 9 mm from the +z plane as felt (one contact: the noise, 3 sigma).
    EXPECT_NEAR(kept.z(), kHalf - kMargin, 3 * kNoiseM) << "seed " << seed;
    EXPECT_NEAR(kept.x(), 0.004, 3 * kNoiseM);  // along the face, away from that edge only
    EXPECT_NEAR(kept.y(), tip.y(), 3 * kNoiseM);
    EXPECT_NEAR(moved, (kept - tip).norm(), 1e-12);
    // Past the felt plane: on the next face, where the gait sends it over the edge.
    const Eigen::Vector3d past = OverMinusY(0.0, 0.030);
    EXPECT_EQ(KeepInsideFace(past, surface, kMinusYFlat, On()), past);
  }
}

TEST(FaceBoundsTest, APointWellInsideItsFaceStaysWhereItIs) {
  const SurfaceModel surface = CubeHeldAtFourFaces(1);
  for (const Eigen::Vector3d& tip : {OverMinusY(0, 0), OverMinusY(0.02, 0.012)}) {
    double moved = 1.0;
    EXPECT_EQ(KeepInsideFace(tip, surface, kMinusYFlat, On(), &moved), tip);
    EXPECT_EQ(moved, 0.0);
  }
  // Over the +z face (its tip outside that plane more than any other): not this face's to bound.
  const Eigen::Vector3d over_top(0.0, -0.010, kHalf + kTip);
  EXPECT_EQ(KeepInsideFace(over_top, surface, kMinusYFlat, On()), over_top);
  // Off (margin 0), nothing moves.
  const Eigen::Vector3d near_edge = OverMinusY(0.0, 0.022);
  EXPECT_EQ(KeepInsideFace(near_edge, surface, kMinusYFlat, FaceBoundsParams{}), near_edge);
}

TEST(FaceBoundsTest, AFaceNotFeltFlatIsNotBounded) {
  const SurfaceModel surface = CubeHeldAtFourFaces(2);
  const Eigen::Vector3d tip = OverMinusY(0.0, 0.022);
  EXPECT_EQ(KeepInsideFace(tip, surface, {}, On()), tip);
  // Flat faces elsewhere (+y, or a plane parallel to -y a centimetre in) do not make -y flat.
  const std::vector<FlatFace> others = {{{0.0, kHalf, 0.0}, Eigen::Vector3d::UnitY()},
                                        {{0.0, -kHalf + 0.01, 0.0}, -Eigen::Vector3d::UnitY()}};
  EXPECT_EQ(KeepInsideFace(tip, surface, others, On()), tip);
}

TEST(FaceBoundsTest, AHexagonalPrismsEndBoundsItsSidesButOneSideNotTheNext) {
  // The prism standing on its end (axis z, r 2.5 cm, 6 cm): one side felt flat, the side 60 deg
  // round (1.05 rad, under min_angle_rad) and the +z end each felt once.
  std::mt19937 rng(7);
  SurfaceModel surface;
  const double apothem = 0.025 * std::cos(M_PI / 6);
  const Eigen::Vector3d side(1, 0, 0), next(std::cos(M_PI / 3), std::sin(M_PI / 3), 0);
  const Eigen::Vector3d end = Eigen::Vector3d::UnitZ();
  Feel(&surface, {apothem * side, apothem * side + Eigen::Vector3d(0, 0, -0.015)}, side, &rng);
  const std::vector<FlatFace> flat = {{apothem * side, side}};
  Feel(&surface, {apothem * next}, next, &rng);
  Feel(&surface, {0.03 * end}, end, &rng);
  // 4 mm below the end's edge and 3 mm from the next side's: moved down the side only.
  const Eigen::Vector3d tip(apothem + kTip, 0.0125 - 0.003, 0.026);
  const Eigen::Vector3d kept = KeepInsideFace(tip, surface, flat, On());
  EXPECT_NEAR(kept.z(), 0.03 - kMargin, 3 * kNoiseM);
  EXPECT_NEAR(kept.y(), tip.y(), 3 * kNoiseM);
}

TEST(FaceBoundsTest, ASlideRoundASphereFeelsNoFaceAndASlideOverAFaceFeelsOne) {
  // Round a 2 cm sphere at 1 cm/s, its normal turning by travel / R: never flat.
  FlatFaceDetector round;
  for (int i = 0; i <= 300; ++i) {
    const double a = 0.0001 * i / 0.02;
    const Eigen::Vector3d n(std::cos(a), std::sin(a), 0.0);
    EXPECT_FALSE(round.Add(0.01 * i, 0.02 * n, n).has_value()) << i;
  }
  // Over a face, with the pose estimate's noise on every point (white: harsher than the filtered
  // estimate's drift): flat once it has gone 1.2 cm, give or take the noise's few millimetres.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, kNoiseM);
  FlatFaceDetector over;
  int found = -1;
  for (int i = 0; i <= 300 && found < 0; ++i) {
    const Eigen::Vector3d p(0.0001 * i + noise(rng), -kHalf + noise(rng), noise(rng));
    if (over.Add(0.01 * i, p, -Eigen::Vector3d::UnitY())) found = i;
  }
  EXPECT_GT(found, 60);
  EXPECT_LT(found, 180);
  // A contact that holds still under the same noise: no slide, no face.
  FlatFaceDetector still;
  for (int i = 0; i <= 300; ++i) {
    const Eigen::Vector3d p(noise(rng), -kHalf + noise(rng), noise(rng));
    EXPECT_FALSE(still.Add(0.01 * i, p, -Eigen::Vector3d::UnitY()).has_value()) << i;
  }
}

}  // namespace
}  // namespace dmpl
