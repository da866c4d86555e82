#include "components/controller/weight_observer.h"

#include <gtest/gtest.h>

#include <random>

namespace dmpl {
namespace {

constexpr double kDt = 0.001;
const Eigen::Vector3d kDown = -Eigen::Vector3d::UnitX();  // the palm up

// The tips' summed force as a held object's chattering contacts give it: its weight along
// gravity, each tick off by 0.65 N in a random direction (as measured on the random goals).
Eigen::Vector3d Chattering(double weight, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, 0.65 / std::sqrt(3.0));
  return weight * kDown + Eigen::Vector3d(noise(*rng), noise(*rng), noise(*rng));
}

TEST(WeightObserverTest, TheWeightComesOutOfTheChatterAfterASecondOfHolding) {
  WeightObserver o(WeightObserverParams{});
  std::mt19937 rng(1);
  double t = 0.0;
  for (; t < 0.5; t += kDt) o.Update(t, Chattering(0.49, &rng), kDown, true);
  EXPECT_EQ(o.weight(), 0.0);  // not yet
  for (; t < 5.0; t += kDt) o.Update(t, Chattering(0.49, &rng), kDown, true);
  // The low-pass over 0.1 s leaves about 0.65 / sqrt(100) = 0.065 N on each sample; the median
  // of 500 of them (not independent over 0.1 s: about 50) lands within 0.05 N.
  EXPECT_NEAR(o.weight(), 0.49, 0.05);
}

TEST(WeightObserverTest, GraspsItCannotReadFromTeachNothing) {
  WeightObserver o(WeightObserverParams{});
  std::mt19937 rng(2);
  double t = 0.0;
  for (; t < 3.0; t += kDt) o.Update(t, Chattering(1.47, &rng), kDown, true);
  const double heavy = o.weight();
  EXPECT_NEAR(heavy, 1.47, 0.05);
  // A link that carries the load leaves the tips feeling less; such ticks are not read, nor
  // ticks without gravity's direction.
  for (; t < 20.0; t += kDt) {
    o.Update(t, Chattering(0.2, &rng), kDown, false);
    o.Update(t, Chattering(0.2, &rng), Eigen::Vector3d::Zero(), true);
  }
  EXPECT_DOUBLE_EQ(o.weight(), heavy);
}

TEST(WeightObserverTest, OnlyThePartAlongGravityCounts) {
  // The palm sideways (gravity along -y): a squeeze's unbalanced push along x is no weight.
  WeightObserver o(WeightObserverParams{});
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitY();
  for (double t = 0.0; t < 3.0; t += kDt) {
    o.Update(t, 0.98 * down + Eigen::Vector3d(0.8, 0.0, 0.3), down, true);
  }
  EXPECT_NEAR(o.weight(), 0.98, 1e-9);
}

}  // namespace
}  // namespace dmpl
