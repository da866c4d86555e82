#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tools/calibrate/fits.h"

namespace dmpl::calib {
namespace {

// Synthetic ticks: four fingers touching, sensed = scale * true + bias + noise, positions offset.
LogData Synthetic(double scale, double bias, const Eigen::Vector3d& offset, int ticks = 2000) {
  LogData data;
  data.fingers = {"T", "F", "M", "R"};
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.01), pos_noise(0.0, 0.0003);
  std::uniform_real_distribution<double> force(0.1, 1.5), angle(-1.0, 1.0);
  for (int k = 0; k < ticks; ++k) {
    Tick& t = data.ticks[k];
    t.has_sensed = t.has_truth = true;
    for (int f = 0; f < 4; ++f) {
      TipSample truth;
      truth.in_contact = true;
      truth.force = force(rng);
      // Points on a sphere of radius 0.025 about (0.07, 0, 0.015), all over it.
      Eigen::Vector3d dir(angle(rng), angle(rng), angle(rng));
      truth.position = Eigen::Vector3d(0.07, 0.0, 0.015) + 0.025 * dir.normalized();
      TipSample sensed = truth;
      sensed.force = scale * truth.force + bias + noise(rng);
      sensed.position = truth.position + offset +
                        Eigen::Vector3d(pos_noise(rng), pos_noise(rng), pos_noise(rng));
      // A few outliers (slips): the robust loss must not follow them.
      if (k % 97 == 0) sensed.force += 2.0;
      t.truth.push_back(truth);
      t.sensed.push_back(sensed);
    }
  }
  return data;
}

TEST(FitsTest, RecoverForceScaleBiasAndContactOffset) {
  const Eigen::Vector3d offset(0.002, -0.001, 0.0015);
  const LogData data = Synthetic(1.2, 0.05, offset);
  const FitResult force = FitForce(data);
  ASSERT_TRUE(force.ok) << force.message;
  EXPECT_NEAR(force.Get("force_scale"), 1.2, 0.01);
  EXPECT_NEAR(force.Get("force_bias"), 0.05, 0.005);
  EXPECT_LT(force.rms_after, force.rms_before);
  EXPECT_GT(force.params[0].stddev, 0.0);
  EXPECT_LT(force.params[0].stddev, 0.01);
  const FitResult pos = FitContactOffset(data);
  ASSERT_TRUE(pos.ok) << pos.message;
  EXPECT_NEAR(pos.Get("offset_x"), 0.002, 1e-4);
  EXPECT_NEAR(pos.Get("offset_y"), -0.001, 1e-4);
  EXPECT_NEAR(pos.Get("offset_z"), 0.0015, 1e-4);
}

TEST(FitsTest, SurfaceFromContactPositionsAlone) {
  const LogData data = Synthetic(1.0, 0.0, Eigen::Vector3d::Zero());
  const FitResult s = FitSurface(data, Eigen::Vector3d::Zero());
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_NEAR(s.Get("radius"), 0.025, 5e-4);
  EXPECT_NEAR(s.Get("centre_x"), 0.07, 5e-4);
  EXPECT_NEAR(s.Get("centre_z"), 0.015, 5e-4);
}

TEST(FitsTest, TooFewSamplesAndNoExcitationAreClearErrors) {
  LogData few = Synthetic(1.0, 0.0, Eigen::Vector3d::Zero(), 10);
  try {
    FitForce(few);
    FAIL();
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("need at least"), std::string::npos) << e.what();
  }
  LogData flat = Synthetic(1.0, 0.0, Eigen::Vector3d::Zero());
  for (auto& [seq, tick] : flat.ticks) {
    for (auto& t : tick.truth) t.force = 0.5;
  }
  try {
    FitForce(flat);
    FAIL();
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("no excitation"), std::string::npos) << e.what();
  }
  LogData no_controller = Synthetic(1.0, 0.0, Eigen::Vector3d::Zero());
  std::vector<FingerModel> models;
  try {
    FitForceResponse(no_controller, &models);
    FAIL();
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("DMPL_CONTROLLER_STATUS"), std::string::npos);
  }
}

// Composite-grip ticks of two fingers: T's force follows F' = F + a (K d - F) on a varying
// commanded penetration d; F's stays where it is whatever it is told (it presses on something
// other than its sensor).
LogData ForceResponses(int ticks) {
  LogData data;
  data.fingers = {"T", "F"};
  double force_t = 0.8;
  for (int k = 0; k < ticks; ++k) {
    Tick& t = data.ticks[k];
    t.has_control = true;
    const double d = 0.002 + 0.001 * std::sin(k / 50.0);
    for (int f = 0; f < 2; ++f) {
      ControlSample c;
      c.primitive = 2;
      c.in_contact = true;
      c.force = f == 0 ? force_t : 0.5;
      c.tip = Eigen::Vector3d::Zero();
      c.contact = Eigen::Vector3d(0, 0, 0.012);
      c.target = Eigen::Vector3d(0, 0, d);
      t.control.push_back(c);
    }
    force_t += 0.03 * (400.0 * d - force_t);
  }
  return data;
}

TEST(FitsTest, AFingerWhoseForceDoesNotFollowIsLeftOutOfTheGains) {
  std::vector<FingerModel> models;
  const FitResult r = FitForceResponse(ForceResponses(3000), &models);
  ASSERT_TRUE(r.ok) << r.message;
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].finger, "T");
  EXPECT_NEAR(models[0].stiffness, 400.0, 4.0);
  EXPECT_NEAR(models[0].rate, 0.03, 0.001);
  EXPECT_NE(r.message.find("left out of the gains: F"), std::string::npos) << r.message;
}

TEST(FitsTest, ChosenGainsAreStableAndBetterThanPoorOnes) {
  const std::vector<FingerModel> models = {{"T", 500.0, 0.02}, {"M", 250.0, 0.05}};
  PiGains chosen;
  const FitResult r = ChooseForceGains(models, 1e-3, 0.1, 0.8, {0.0002, 0.005}, "grip", &chosen);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_LT(r.rms_after, r.rms_before);
  EXPECT_LE(chosen.kp * 500.0, 1.0 + 1e-3);  // the loop-gain margin
  EXPECT_GT(chosen.ki, 0.0);
}

}  // namespace
}  // namespace dmpl::calib
