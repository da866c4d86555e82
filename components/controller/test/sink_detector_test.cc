#include "components/controller/sink_detector.h"

#include <gtest/gtest.h>

#include <random>

namespace dmpl {
namespace {

constexpr double kDt = 0.001;
const Eigen::Vector3d kGravity(-9.81, 0.0, 0.0);  // the palm up: down is -x

using Tips = std::vector<std::optional<Eigen::Vector3d>>;

SinkDetectorParams On() {
  SinkDetectorParams p;
  p.enabled = true;  // 50 mm/s over 20 ms, 0.2 s refractory
  return p;
}

// Three grip tips (T, F, R; M explores) about a held object, all moved by `shift`.
Tips GripAround(const Eigen::Vector3d& shift) {
  return {Eigen::Vector3d(0.07, 0.0, -0.022) + shift, Eigen::Vector3d(0.07, 0.037, 0.015) + shift,
          std::nullopt, Eigen::Vector3d(0.07, -0.037, 0.015) + shift};
}

// Ticks from `t` to `until`, the grip moving at `velocity`; the times of the sinks said.
std::vector<double> Tick(SinkDetector* d, double* t, double until, const Eigen::Vector3d& velocity,
                        Eigen::Vector3d* at, bool exploring = true,
                        const Eigen::Vector3d& gravity = kGravity) {
  std::vector<double> sinks;
  for (; *t < until - 1e-9; *t += kDt) {
    *at += velocity * kDt;
    if (d->Update(*t, GripAround(*at), gravity, exploring)) sinks.push_back(*t);
  }
  return sinks;
}

TEST(SinkDetectorTest, AGripSinkingAlongGravityIsSaidOnceWithinTheWindow) {
  SinkDetector d(On());
  double t = 0.0;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  EXPECT_TRUE(Tick(&d, &t, 0.5, Eigen::Vector3d::Zero(), &at).empty());  // held still
  // The object sinks at 80 mm/s (the slick sphere's squeeze-out 40 ms in): said once the
  // window holds half its 20 ms of it, and once only within the refractory 0.2 s.
  const std::vector<double> sinks = Tick(&d, &t, 0.65, Eigen::Vector3d(-0.08, 0, 0), &at);
  ASSERT_EQ(sinks.size(), 1u);
  EXPECT_GE(sinks[0], 0.5 + 0.5 * On().window_s - 1e-9);
  EXPECT_LE(sinks[0], 0.5 + On().window_s + 2 * kDt);
  EXPECT_NEAR(d.speed(), 0.08, 1e-6);
  // Still sinking after the refractory time: said again.
  EXPECT_EQ(Tick(&d, &t, 0.8, Eigen::Vector3d(-0.08, 0, 0), &at).size(), 1u);
}

TEST(SinkDetectorTest, MotionAcrossOrAgainstGravityOrSlowerIsNoSink) {
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(0, 0.2, 0), Eigen::Vector3d(0, 0, -0.2),
                                   Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(-0.04, 0, 0)}) {
    SinkDetector d(On());
    double t = 0.0;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    EXPECT_TRUE(Tick(&d, &t, 0.3, v, &at).empty()) << v.transpose();
  }
}

TEST(SinkDetectorTest, NothingIsSaidWithoutAnExplorerGravityOrTheDetector) {
  const Eigen::Vector3d sink(-0.1, 0, 0);
  {
    SinkDetector d(On());  // all four grip: the grip turning the object moves its tips
    double t = 0.0;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    EXPECT_TRUE(Tick(&d, &t, 0.3, sink, &at, /*exploring=*/false).empty());
  }
  {
    SinkDetector d(On());
    double t = 0.0;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    EXPECT_TRUE(Tick(&d, &t, 0.3, sink, &at, true, Eigen::Vector3d::Zero()).empty());
  }
  {
    SinkDetector d(SinkDetectorParams{});  // off by default
    double t = 0.0;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    EXPECT_TRUE(Tick(&d, &t, 0.3, sink, &at).empty());
  }
}

TEST(SinkDetectorTest, AFingerJoiningTheGripRestartsTheWindowInsteadOfMovingItsMean) {
  // M (its tip 2.5 cm lower than the others' mean, along gravity) takes hold: the tips' mean
  // jumps by 6 mm along gravity in one tick, which is no sink.
  SinkDetector d(On());
  double t = 0.0;
  const Tips three = GripAround(Eigen::Vector3d::Zero());
  for (; t < 0.1; t += kDt) EXPECT_FALSE(d.Update(t, three, kGravity, true));
  Tips four = three;
  four[2] = Eigen::Vector3d(0.045, 0.0, 0.05);
  for (; t < 0.2; t += kDt) EXPECT_FALSE(d.Update(t, four, kGravity, true));
  // One tip alone says nothing of the object (its finger may be rolling), however it moves.
  const Tips one = {std::nullopt, Eigen::Vector3d(0.07, 0.037, 0.015), std::nullopt,
                    std::nullopt};
  for (double x = 0.0; t < 0.3; t += kDt, x -= 0.1 * kDt) {
    Tips moved = one;
    moved[1]->x() += x;
    EXPECT_FALSE(d.Update(t, moved, kGravity, true));
  }
}

}  // namespace
}  // namespace dmpl
