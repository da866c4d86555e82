#include <gtest/gtest.h>

#include <cmath>

#include "sim_process/sim/palm_motion.h"

namespace dmpl {
namespace {

const Eigen::Vector3d kGravity(0, 0, -9.81);

TEST(PalmMotionTest, AStillPalmReadsTheWorldsGravityTurnedIntoIt) {
  const Eigen::Matrix3d up = RotationFromRpy({0.0, -M_PI / 2, 0.0});  // palm x -> world z
  const PalmMotion still(PalmMotionParams{}, up, "test");
  EXPECT_FALSE(still.moves());
  EXPECT_TRUE(still.GravityInPalm(12.0, kGravity).isApprox(Eigen::Vector3d(-9.81, 0, 0), 1e-12));
}

TEST(PalmMotionTest, ATurnStartsOnTimeGoesAtItsRateAndStopsAtItsAngle) {
  PalmMotionParams p;
  p.axis = {0.0, 0.0, 2.0};  // normalised
  p.rate_rad_s = -0.5;
  p.start_s = 1.0;
  p.angle_rad = 1.0;
  const PalmMotion turn(p, Eigen::Matrix3d::Identity(), "test");
  EXPECT_TRUE(turn.moves());
  auto angle_at = [&](double t) {
    const Eigen::AngleAxisd a(turn.Orientation(t));
    return a.angle() * a.axis().z();
  };
  EXPECT_NEAR(angle_at(0.5), 0.0, 1e-12);
  EXPECT_NEAR(angle_at(2.0), -0.5, 1e-12);
  EXPECT_NEAR(angle_at(3.0), -1.0, 1e-12);
  EXPECT_NEAR(angle_at(30.0), -1.0, 1e-12) << "the turn stops at its angle";
}

TEST(PalmMotionTest, ATrajectoryIsSlerpedBetweenItsOrientationsAndHeldOutside) {
  PalmMotionParams p;
  p.trajectory = {{1.0, {0.0, 0.0, 0.0}}, {3.0, {0.0, 0.0, M_PI / 2}}};
  const PalmMotion motion(p, Eigen::Matrix3d::Identity(), "test");
  const auto yaw = [&](double t) {
    const Eigen::Vector3d x = motion.Orientation(t) * Eigen::Vector3d::UnitX();
    return std::atan2(x.y(), x.x());
  };
  EXPECT_NEAR(yaw(0.0), 0.0, 1e-12);
  EXPECT_NEAR(yaw(2.0), M_PI / 4, 1e-12);
  EXPECT_NEAR(yaw(2.5), 3 * M_PI / 8, 1e-12);
  EXPECT_NEAR(yaw(9.0), M_PI / 2, 1e-12);
}

TEST(PalmMotionTest, BadMotionsAreConfigErrorsNamingTheKey) {
  auto error_of = [](const PalmMotionParams& p) -> std::string {
    try {
      PalmMotion(p, Eigen::Matrix3d::Identity(), "palm.yaml");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  PalmMotionParams zero_axis;
  zero_axis.rate_rad_s = 0.1;
  zero_axis.axis = {0, 0, 0};
  EXPECT_NE(error_of(zero_axis).find("palm.yaml: key 'sim.palm_motion.axis'"), std::string::npos)
      << error_of(zero_axis);
  PalmMotionParams both;
  both.rate_rad_s = 0.1;
  both.trajectory = {{0.0, {0, 0, 0}}};
  EXPECT_NE(error_of(both).find("'sim.palm_motion.trajectory'"), std::string::npos);
  PalmMotionParams backwards;
  backwards.trajectory = {{1.0, {0, 0, 0}}, {1.0, {0, 0, 1}}};
  EXPECT_NE(error_of(backwards).find("'sim.palm_motion.trajectory[1].t'"), std::string::npos)
      << error_of(backwards);
  PalmMotionParams negative_angle;
  negative_angle.angle_rad = -1.0;
  EXPECT_NE(error_of(negative_angle).find("angle_rad"), std::string::npos) << error_of(negative_angle);
}

}  // namespace
}  // namespace dmpl
