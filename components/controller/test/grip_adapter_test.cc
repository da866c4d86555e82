#include "components/controller/grip_adapter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace dmpl {
namespace {

constexpr double kDt = 0.001;
constexpr double kTip = 0.012;  // fingertip radius

// Contact offsets (contact point - tip centre) of four fingers around an object at the origin,
// each touching it along the direction from its tip to the object's centre.
std::vector<std::optional<Eigen::Vector3d>> Grip(double turn, const Eigen::Vector3d& slide,
                                                 int fingers = 4) {
  std::vector<std::optional<Eigen::Vector3d>> out(4);
  for (int f = 0; f < fingers; ++f) {
    const double a = turn + f * M_PI / 2;
    const Eigen::Vector3d inward(0.0, -std::cos(a), -std::sin(a));
    out[f] = kTip * inward + slide;  // a slide moves every contact over its tip the same way
  }
  return out;
}

TEST(SlipDetectorTest, ASlideIsDetectedWithinFortyTicks) {
  SlipDetector d(0.008, 0.01, 0.05);
  int detected_at = -1;
  for (int k = 0; k < 100; ++k) {
    // The object slides along -z at 2 cm/s from tick 10.
    const double slide = k < 10 ? 0.0 : -0.02 * (k - 10) * kDt;
    if (d.Update(k * kDt, Grip(0.0, {0, 0, slide})) && detected_at < 0) detected_at = k;
  }
  ASSERT_GE(detected_at, 10);
  EXPECT_LE(detected_at - 10, 40);  // the window and the low-pass: 2 cm/s shows within 40 ms
}

TEST(SlipDetectorTest, TurningTheObjectIsNoSlip) {
  // The grip turns the object about x at 0.5 rad/s: the contacts go round their tips in
  // different directions, and their mean stays put.
  SlipDetector d(0.008, 0.01, 0.05);
  for (int k = 0; k < 2000; ++k) {
    EXPECT_FALSE(d.Update(k * kDt, Grip(0.5 * k * kDt, Eigen::Vector3d::Zero()))) << k;
  }
}

TEST(SlipDetectorTest, ChatteringContactsRaiseNoAlarm) {
  // Contact points that jitter by 0.3 mm per tick (simulated tactile chatter), no slide.
  SlipDetector d(0.008, 0.01, 0.05);
  std::mt19937 rng(3);
  std::normal_distribution<double> jitter(0.0, 0.0003);
  for (int k = 0; k < 5000; ++k) {
    auto g = Grip(0.0, Eigen::Vector3d::Zero());
    for (auto& o : g) *o += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    EXPECT_FALSE(d.Update(k * kDt, g)) << k;
  }
}

TEST(SlipDetectorTest, OneContactAloneIsNoEvidence) {
  SlipDetector d(0.008, 0.01, 0.05);
  for (int k = 0; k < 100; ++k) {
    std::vector<std::optional<Eigen::Vector3d>> one(4);
    one[0] = Eigen::Vector3d(0, 0, -0.05 * k * kDt);  // could as well be rolling
    EXPECT_FALSE(d.Update(k * kDt, one));
  }
}

GripAdaptationParams On() {
  GripAdaptationParams p;
  p.enabled = true;
  return p;
}

TEST(GripAdapterTest, OffItKeepsTheNominalGrip) {
  GripAdapter a(GripAdaptationParams{}, 0.8);
  for (int k = 0; k < 1000; ++k) {
    EXPECT_FALSE(a.Update(k * kDt, Grip(0.0, {0, 0, -0.05 * k * kDt}, 3), 3, 4));
  }
  EXPECT_DOUBLE_EQ(a.grip_force(), 0.8);
}

TEST(GripAdapterTest, TheRemainingFingersTakeOverTheExplorersShare) {
  GripAdapter a(On(), 0.8);
  a.Update(0.0, Grip(0.0, Eigen::Vector3d::Zero()), 4, 4);
  EXPECT_DOUBLE_EQ(a.grip_force(), 0.8);
  a.Update(kDt, Grip(0.0, Eigen::Vector3d::Zero(), 3), 3, 4);
  EXPECT_DOUBLE_EQ(a.grip_force(), 0.8 * 4 / 3);
}

TEST(GripAdapterTest, SlipsRaiseTheGripWhichIsKeptAndCapped) {
  const GripAdaptationParams p = On();
  GripAdapter a(p, 0.8);
  double slide = 0.0;
  int slips = 0;
  for (int k = 0; k < 3000; ++k) {
    slide -= 0.03 * kDt;  // a load the grip cannot hold: it slides on and on
    slips += a.Update(k * kDt, Grip(0.0, {0, 0, slide}), 4, 4);
  }
  EXPECT_EQ(slips, a.slips());
  EXPECT_GE(slips, 2);
  EXPECT_NEAR(a.load_scale(), std::pow(p.raise_factor, slips), 1e-12);
  EXPECT_LE(a.grip_force(), p.max_grip_force_n);
  EXPECT_GT(a.grip_force(), p.max_grip_force_n / p.raise_factor);
  // Held again: the learned load stays.
  const double held = a.grip_force();
  for (int k = 3000; k < 5000; ++k) a.Update(k * kDt, Grip(0.0, {0, 0, slide}), 4, 4);
  EXPECT_DOUBLE_EQ(a.grip_force(), held);
}

TEST(GripAdapterTest, AFingerJoiningTheGripIsNoSlip) {
  GripAdapter a(On(), 0.8);
  for (int k = 0; k < 100; ++k) a.Update(k * kDt, Grip(0.0, Eigen::Vector3d::Zero(), 3), 3, 3);
  // The fourth finger's contact appears (a jump of its offset from nothing).
  for (int k = 100; k < 200; ++k)
    EXPECT_FALSE(a.Update(k * kDt, Grip(0.0, Eigen::Vector3d::Zero(), 4), 4, 4));
  EXPECT_EQ(a.slips(), 0);
}

}  // namespace
}  // namespace dmpl
