#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "sim_process/noise/noise_injector.h"
#include "sim_process/noise/sensors_translation.h"

namespace dmpl {
namespace {

constexpr int kSamples = 10000;

ObjectPoseReading TruePose() {
  ObjectPoseReading m;
  m.position = {0.05, -0.01, 0.1};
  return m;
}

std::vector<TipReading> TrueTactile(double force) {
  std::vector<TipReading> m(2);
  m[0].finger = "T";
  m[0].in_contact = true;
  m[0].force_n = force;
  m[0].position[2] = 0.1;
  m[1].finger = "R";
  m[1].in_contact = false;
  return m;
}

JointsReading TrueJoints() { return {{"a", "b"}, {0.3, -0.2}, {0.0, 0.0}, {0.0, 0.0}}; }

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
    const auto pose = noise.Sense(k, TruePose());
    const auto joints = noise.Sense(k, TrueJoints());
    const auto tactile = noise.Sense(k, TrueTactile(1.0));
    ASSERT_TRUE(pose && joints && tactile);
    px.push_back(pose->position[0]);
    py.push_back(pose->position[1]);
    pz.push_back(pose->position[2]);
    q0.push_back(joints->position[0]);
    cx.push_back(tactile->at(0).position[0]);
    cz.push_back(tactile->at(0).position[2]);
    f.push_back(tactile->at(0).force_n);
    EXPECT_EQ(tactile->at(1).force_n, 0.0);  // no contact: nothing to sense
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
    const auto pose = noise.Sense(k, TruePose());
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
    const auto ra = a.Sense(k, TruePose());
    const auto rb = b.Sense(k, TruePose());
    const auto rc = c.Sense(k, TruePose());
    EXPECT_EQ(ra->position[0], rb->position[0]);
    EXPECT_NE(ra->position[0], rc->position[0]);
  }
}

TEST(NoiseInjectorTest, ArrivalOrderDoesNotChangeTheReadings) {
  NoiseParams p;
  p.force_sigma = 0.1;
  NoiseInjector a(p, 9), b(p, 9);
  const auto pose_a = a.Sense(7, TruePose());
  const auto tact_a = a.Sense(7, TrueTactile(1.0));
  const auto tact_b = b.Sense(7, TrueTactile(1.0));
  const auto pose_b = b.Sense(7, TruePose());
  EXPECT_EQ(pose_a->position[1], pose_b->position[1]);
  EXPECT_EQ(tact_a->at(0).force_n, tact_b->at(0).force_n);
}

TEST(NoiseInjectorTest, AWholeTickIsItsPartsSensedAlone) {
  NoiseParams p;
  p.force_sigma = 0.1;
  p.joint_position_sigma = 0.01;
  NoiseInjector whole(p, 4), parts(p, 4);
  HandReading truth;
  truth.seq = 3;
  truth.utime = 3000;
  truth.joints = TrueJoints();
  truth.object = TruePose();
  truth.tips = TrueTactile(1.0);
  const auto sensed = whole.Sense(truth);
  ASSERT_TRUE(sensed.has_value());
  EXPECT_EQ(sensed->seq, 3);
  EXPECT_EQ(sensed->utime, 3000);
  EXPECT_EQ(sensed->joints.position, parts.Sense(3, TrueJoints())->position);
  EXPECT_EQ(sensed->object.position[0], parts.Sense(3, TruePose())->position[0]);
  EXPECT_EQ(sensed->tips[0].force_n, parts.Sense(3, TrueTactile(1.0))->at(0).force_n);
  // A malformed part: rejected, nothing forwarded.
  truth.tips[0].force_n = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(whole.Sense(truth).has_value());
  EXPECT_EQ(whole.rejected(), 1);
}

TEST(NoiseInjectorTest, TheIMUsGravityKeepsItsSizeAndTurnsByTheConfiguredAngle) {
  const std::array<double, 3> truth = {-9.81, 0.0, 0.0};
  NoiseInjector exact(NoiseParams{}, 3);
  EXPECT_EQ(*exact.SenseGravity(1, truth), truth);
  NoiseParams p;
  p.gravity_direction_sigma = 0.01;
  NoiseInjector noise(p, 3);
  // A rotation vector with sigma s per axis turns a direction by the norm of its two components
  // across it: a Rayleigh angle of mean s * sqrt(pi / 2).
  double sum = 0.0;
  for (int k = 0; k < kSamples; ++k) {
    const auto g = noise.SenseGravity(k, truth);
    ASSERT_TRUE(g);
    const Eigen::Vector3d v((*g)[0], (*g)[1], (*g)[2]);
    EXPECT_NEAR(v.norm(), 9.81, 1e-9);
    sum += std::acos(std::clamp(-v.x() / v.norm(), -1.0, 1.0));
  }
  EXPECT_NEAR(sum / kSamples, 0.01 * std::sqrt(M_PI / 2), 0.03 * 0.01 * std::sqrt(M_PI / 2));
  EXPECT_FALSE(noise.SenseGravity(1, {std::nan(""), 0.0, 0.0}));
  EXPECT_EQ(noise.rejected(), 1);
}

TEST(SensorsTranslationTest, AMessageAndItsReadingCarryTheSameValues) {
  hand_sensors_t m{};
  m.seq = m.joints.seq = m.object.seq = m.tactile.seq = 7;
  m.utime = m.joints.utime = m.object.utime = m.tactile.utime = 7000;
  m.joints.name = {"a", "b"};
  m.joints.num_joints = 2;
  m.joints.position = {0.3, -0.2};
  m.joints.velocity = {0.1, 0.2};
  m.joints.effort = {0.01, 0.02};
  m.object.valid = true;
  m.object.position[1] = 0.02;
  m.object.orientation[0] = 1.0;
  m.object.angular_velocity[2] = 0.5;
  fingertip_contact_t tip{};
  tip.finger = "T";
  tip.in_contact = true;
  tip.position[0] = 0.04;
  tip.normal[2] = 1.0;
  tip.force_n = 0.8;
  tip.num_points = 2;
  m.tactile.fingers = {tip};
  m.tactile.num_fingers = 1;
  m.gravity[0] = -9.7;
  m.gravity[2] = 0.3;
  std::string why;
  const auto reading = ToReading(m, &why);
  ASSERT_TRUE(reading) << why;
  const hand_sensors_t back = ToMessage(*reading);
  std::vector<uint8_t> a(m.getEncodedSize()), b(back.getEncodedSize());
  m.encode(a.data(), 0, static_cast<int>(a.size()));
  back.encode(b.data(), 0, static_cast<int>(b.size()));
  EXPECT_EQ(a, b);  // every field, bit for bit
  // Parts of another tick, or arrays that disagree with their counts: not one tick's reading.
  m.object.seq = 6;
  EXPECT_FALSE(ToReading(m, &why));
  EXPECT_NE(why.find("parts of other ticks"), std::string::npos);
  m.object.seq = 7;
  m.joints.num_joints = 3;
  EXPECT_FALSE(ToReading(m, &why));
  EXPECT_NE(why.find("inconsistent sizes"), std::string::npos);
}

TEST(NoiseInjectorTest, NanInputIsRejectedAndNeverForwarded) {
  NoiseInjector noise(NoiseParams{}, 1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ObjectPoseReading pose = TruePose();
  pose.position[1] = nan;
  EXPECT_FALSE(noise.Sense(1, pose));
  pose = TruePose();
  pose.orientation[0] = 2.0;
  EXPECT_FALSE(noise.Sense(2, pose));
  EXPECT_FALSE(noise.Sense(1, TrueTactile(nan)));
  JointsReading joints = TrueJoints();
  joints.velocity[1] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(noise.Sense(1, joints));
  joints = TrueJoints();
  joints.names.push_back("c");
  EXPECT_FALSE(noise.Sense(2, joints));
  EXPECT_EQ(noise.rejected(), 5);
  // And good input still flows afterwards.
  EXPECT_TRUE(noise.Sense(3, TruePose()));
}

TEST(NoiseInjectorTest, DelayShiftsTruthByTicks) {
  NoiseParams p;
  p.object_position_sigma = 0.0;
  p.delay_ticks = 2;
  NoiseInjector noise(p, 1);
  for (int k = 0; k < 5; ++k) {
    ObjectPoseReading truth = TruePose();
    truth.position[0] = k;
    const auto out = noise.Sense(k, truth);
    EXPECT_EQ(out->position[0], std::max(0, k - 2));
  }
}

TEST(NoiseInjectorTest, DropoutMarksPoseInvalidAtTheConfiguredRate) {
  NoiseParams p;
  p.dropout_probability = 0.2;
  NoiseInjector noise(p, 11);
  int invalid = 0;
  for (int k = 0; k < kSamples; ++k) invalid += noise.Sense(k, TruePose())->valid ? 0 : 1;
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
