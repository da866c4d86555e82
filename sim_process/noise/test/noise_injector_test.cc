#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sim_process/noise/noise_injector.h"

namespace dmpl {
namespace {

constexpr int kSamples = 10000;

object_pose_t TruePose(int64_t seq) {
  object_pose_t m{};
  m.seq = seq;
  m.utime = seq * 1000;
  m.valid = true;
  m.position[0] = 0.05;
  m.position[1] = -0.01;
  m.position[2] = 0.1;
  m.orientation[0] = 1.0;
  return m;
}

tactile_t TrueTactile(int64_t seq, double force) {
  tactile_t m{};
  m.seq = seq;
  m.num_fingers = 2;
  m.fingers.resize(2);
  m.fingers[0].finger = "T";
  m.fingers[0].in_contact = true;
  m.fingers[0].force_n = force;
  m.fingers[0].position[2] = 0.1;
  m.fingers[1].finger = "R";
  m.fingers[1].in_contact = false;
  return m;
}

joint_state_t TrueJoints(int64_t seq) {
  joint_state_t m{};
  m.seq = seq;
  m.num_joints = 2;
  m.name = {"a", "b"};
  m.position = {0.3, -0.2};
  m.velocity = {0.0, 0.0};
  m.effort = {0.0, 0.0};
  return m;
}

struct Stats {
  double mean = 0, sigma = 0;
};
Stats Of(const std::vector<double>& x) {
  Stats s;
  for (double v : x) s.mean += v;
  s.mean /= x.size();
  for (double v : x) s.sigma += (v - s.mean) * (v - s.mean);
  s.sigma = std::sqrt(s.sigma / (x.size() - 1));
  return s;
}

// Mean within 3 standard errors (sigma/sqrt(N)) and sigma within 3 standard errors of a
// Gaussian's sample standard deviation (sigma/sqrt(2(N-1))).
void ExpectGaussian(const std::vector<double>& x, double mean, double sigma, const char* what) {
  const Stats s = Of(x);
  const double n = static_cast<double>(x.size());
  EXPECT_NEAR(s.mean, mean, 3 * sigma / std::sqrt(n)) << what;
  EXPECT_NEAR(s.sigma, sigma, 3 * sigma / std::sqrt(2 * (n - 1))) << what;
}

TEST(NoiseInjectorTest, EveryNoisedFieldHasTheConfiguredMeanAndSigma) {
  NoiseParams p;
  p.object_position_sigma = 0.005;
  p.joint_position_sigma = 0.01;
  p.contact_position_sigma = 0.002;
  p.contact_position_offset = {0.001, 0.0, -0.002};
  p.force_sigma = 0.05;
  p.force_bias = 0.1;
  p.force_scale = 1.2;
  NoiseInjector noise(p, 42);
  std::vector<double> px, py, pz, q0, cx, cz, f;
  for (int k = 0; k < kSamples; ++k) {
    const auto pose = noise.Sense(TruePose(k));
    const auto joints = noise.Sense(TrueJoints(k));
    const auto tactile = noise.Sense(TrueTactile(k, 1.0));
    ASSERT_TRUE(pose && joints && tactile);
    px.push_back(pose->position[0]);
    py.push_back(pose->position[1]);
    pz.push_back(pose->position[2]);
    q0.push_back(joints->position[0]);
    cx.push_back(tactile->fingers[0].position[0]);
    cz.push_back(tactile->fingers[0].position[2]);
    f.push_back(tactile->fingers[0].force_n);
    EXPECT_EQ(tactile->fingers[1].force_n, 0.0);  // no contact: nothing to sense
    EXPECT_EQ(pose->seq, k);
  }
  ExpectGaussian(px, 0.05, 0.005, "object x");
  ExpectGaussian(py, -0.01, 0.005, "object y");
  ExpectGaussian(pz, 0.1, 0.005, "object z");
  ExpectGaussian(q0, 0.3, 0.01, "joint 0");
  ExpectGaussian(cx, 0.001, 0.002, "contact x");
  ExpectGaussian(cz, 0.1 - 0.002, 0.002, "contact z");
  ExpectGaussian(f, 1.2 * 1.0 + 0.1, 0.05, "force");
}

TEST(NoiseInjectorTest, OrientationNoiseHasTheConfiguredAngleSpread) {
  NoiseParams p;
  p.object_orientation_sigma = 0.02;
  NoiseInjector noise(p, 3);
  std::vector<double> rx;
  for (int k = 0; k < kSamples; ++k) {
    const auto pose = noise.Sense(TruePose(k));
    ASSERT_TRUE(pose);
    // Small rotation about x: 2 * qx ~= angle.
    rx.push_back(2.0 * pose->orientation[1] / pose->orientation[0]);
  }
  ExpectGaussian(rx, 0.0, 0.02, "rotation about x");
}

TEST(NoiseInjectorTest, SameSeedSameOutputDifferentSeedDifferentOutput) {
  NoiseParams p;
  NoiseInjector a(p, 5), b(p, 5), c(p, 6);
  for (int k = 0; k < 100; ++k) {
    const auto ra = a.Sense(TruePose(k));
    const auto rb = b.Sense(TruePose(k));
    const auto rc = c.Sense(TruePose(k));
    EXPECT_EQ(ra->position[0], rb->position[0]);
    EXPECT_NE(ra->position[0], rc->position[0]);
  }
}

TEST(NoiseInjectorTest, ArrivalOrderDoesNotChangeTheReadings) {
  NoiseParams p;
  p.force_sigma = 0.1;
  NoiseInjector a(p, 9), b(p, 9);
  const auto pose_a = a.Sense(TruePose(7));
  const auto tact_a = a.Sense(TrueTactile(7, 1.0));
  const auto tact_b = b.Sense(TrueTactile(7, 1.0));
  const auto pose_b = b.Sense(TruePose(7));
  EXPECT_EQ(pose_a->position[1], pose_b->position[1]);
  EXPECT_EQ(tact_a->fingers[0].force_n, tact_b->fingers[0].force_n);
}

TEST(NoiseInjectorTest, AWholeTickIsItsPartsSensedAlone) {
  NoiseParams p;
  p.force_sigma = 0.1;
  p.joint_position_sigma = 0.01;
  NoiseInjector whole(p, 4), parts(p, 4);
  hand_sensors_t truth{};
  truth.seq = 3;
  truth.utime = 3000;
  truth.joints = TrueJoints(3);
  truth.object = TruePose(3);
  truth.tactile = TrueTactile(3, 1.0);
  const auto sensed = whole.Sense(truth);
  ASSERT_TRUE(sensed.has_value());
  EXPECT_EQ(sensed->seq, 3);
  EXPECT_EQ(sensed->joints.position, parts.Sense(TrueJoints(3))->position);
  EXPECT_EQ(sensed->object.position[0], parts.Sense(TruePose(3))->position[0]);
  EXPECT_EQ(sensed->tactile.fingers[0].force_n,
            parts.Sense(TrueTactile(3, 1.0))->fingers[0].force_n);
  // Parts of another tick, or a malformed part: rejected, nothing forwarded.
  truth.object.seq = 2;
  EXPECT_FALSE(whole.Sense(truth).has_value());
  truth.object.seq = 3;
  truth.tactile.fingers[0].force_n = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(whole.Sense(truth).has_value());
  EXPECT_EQ(whole.rejected(), 2);
}

TEST(NoiseInjectorTest, NanInputIsRejectedAndNeverForwarded) {
  NoiseInjector noise(NoiseParams{}, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  object_pose_t pose = TruePose(1);
  pose.position[1] = nan;
  EXPECT_FALSE(noise.Sense(pose));
  pose = TruePose(2);
  pose.orientation[0] = 2.0;
  EXPECT_FALSE(noise.Sense(pose));
  tactile_t tactile = TrueTactile(1, nan);
  EXPECT_FALSE(noise.Sense(tactile));
  joint_state_t joints = TrueJoints(1);
  joints.velocity[1] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(noise.Sense(joints));
  joints = TrueJoints(2);
  joints.num_joints = 3;
  EXPECT_FALSE(noise.Sense(joints));
  EXPECT_EQ(noise.rejected(), 5);
  // And good input still flows afterwards.
  EXPECT_TRUE(noise.Sense(TruePose(3)));
}

TEST(NoiseInjectorTest, DelayShiftsTruthByTicksButKeepsSeq) {
  NoiseParams p;
  p.object_position_sigma = 0.0;
  p.delay_ticks = 2;
  NoiseInjector noise(p, 1);
  for (int k = 0; k < 5; ++k) {
    object_pose_t truth = TruePose(k);
    truth.position[0] = k;
    const auto out = noise.Sense(truth);
    EXPECT_EQ(out->seq, k);
    EXPECT_EQ(out->position[0], std::max(0, k - 2));
  }
}

TEST(NoiseInjectorTest, DropoutMarksPoseInvalidAtTheConfiguredRate) {
  NoiseParams p;
  p.dropout_probability = 0.2;
  NoiseInjector noise(p, 11);
  int invalid = 0;
  for (int k = 0; k < kSamples; ++k) invalid += noise.Sense(TruePose(k))->valid ? 0 : 1;
  // Binomial: sd = sqrt(N p (1-p)) = 40; allow 3 sd.
  EXPECT_NEAR(invalid, 0.2 * kSamples, 3 * 40.0);
}

TEST(NoiseParamsTest, RejectsNonsense) {
  NoiseParams p;
  p.object_position_sigma = -1;
  EXPECT_THROW(p.Validate("x.yaml"), ConfigError);
  p = NoiseParams{};
  p.dropout_probability = 1.5;
  EXPECT_THROW(p.Validate("x.yaml"), ConfigError);
  p = NoiseParams{};
  p.force_scale = 0;
  EXPECT_THROW(p.Validate("x.yaml"), ConfigError);
}

}  // namespace
}  // namespace dmpl
