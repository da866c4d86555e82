#include "supervisor/gait_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dmpl {
namespace {

// Four fingertips 90 deg apart around the x axis, `r` from an object centred at the origin, as
// they stood when the task began (their homes) and as they stand now.
struct Ring {
  explicit Ring(double r) {
    view.fingers.resize(4);
    for (int k = 0; k < 4; ++k) {
      const double a = M_PI / 2 * k;
      home.emplace_back(0.0, r * std::cos(a), r * std::sin(a));
      view.fingers[k].tip = home.back();
      view.fingers[k].in_contact = true;
    }
  }
  GaitGeometry Geometry(double clearance, double max_deviation = 0.0) const {
    GaitSpec spec;
    spec.tip_clearance_m = clearance;
    return GaitGeometry(home, Eigen::Vector3d::Zero(), spec, max_deviation);
  }
  std::vector<Eigen::Vector3d> home;
  ControllerView view;
};

TEST(GaitGeometryTest, TheExplorersPointLiesOnTheFeltSurfaceWhereItIsKnown) {
  // Homes 3.7 cm from the centre (a 2.5 cm sphere and 1.2 cm tips); the object is a box 2 cm
  // from its centre along +y (a face felt at many points), unexplored elsewhere.
  const Ring ring(0.037);
  const GaitGeometry g = ring.Geometry(0.0);
  SurfaceModel surface;
  for (double u = -0.008; u <= 0.008; u += 0.004) {
    for (double v = -0.008; v <= 0.008; v += 0.004) {
      surface.Add(Eigen::Isometry3d::Identity(), Eigen::Vector3d(u, 0.02, v),
                  Eigen::Vector3d::UnitY(), 0.0);
    }
  }
  const Eigen::AngleAxisd none(0.0, Eigen::Vector3d::UnitX());
  // Finger 0 (home along +y): on the face, a tip radius out, not at the home's 3.7 cm.
  const Eigen::Vector3d on_face = g.ExplorePoint(0, none, ring.view, surface, 0.012);
  EXPECT_NEAR(on_face.y(), 0.032, 1e-9);
  EXPECT_NEAR(on_face.z(), 0.0, 1e-9);
  // A face felt where the home's sphere has it (2.5 cm: 3.7 cm less the tip), within 3 mm:
  // the home's point stands.
  SurfaceModel agreeing;
  for (double u = -0.008; u <= 0.008; u += 0.004) {
    agreeing.Add(Eigen::Isometry3d::Identity(), Eigen::Vector3d(u, 0.0235, 0.0),
                 Eigen::Vector3d::UnitY(), 0.0);
    agreeing.Add(Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.0, 0.0235, u),
                 Eigen::Vector3d::UnitY(), 0.0);
  }
  EXPECT_TRUE(g.ExplorePoint(0, none, ring.view, agreeing, 0.012).isApprox(ring.home[0]));
  // Where nothing was felt (finger 2, along -y), or before any tip radius is known: the home.
  EXPECT_TRUE(g.ExplorePoint(2, none, ring.view, surface, 0.012).isApprox(ring.home[2]));
  EXPECT_TRUE(g.ExplorePoint(0, none, ring.view, surface, 0.0).isApprox(ring.home[0]));
  // The model is in the object's frame: turned with the object, the face turns with it.
  ControllerView turned = ring.view;
  turned.object.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).matrix();
  const Eigen::Vector3d to_z = g.ExplorePoint(1, none, turned, surface, 0.012);  // home +z
  EXPECT_NEAR(to_z.z(), 0.032, 1e-9);
}

TEST(GaitGeometryTest, AnExplorersPointAboveTheEquatorIsLoweredAlongItsMeridianOverThePalm) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitX();  // palm up: gravity along -x
  // 30 deg above the level, lowered to 5 deg: same distance, same direction across the level.
  const Eigen::Vector3d high(0.037 * std::sin(0.5236), 0.037 * std::cos(0.5236), 0.0);
  const Eigen::Vector3d lowered = BelowElevation(high, up, 0.0873);
  EXPECT_NEAR(lowered.norm(), 0.037, 1e-12);
  EXPECT_NEAR(std::asin(lowered.dot(up) / lowered.norm()), 0.0873, 1e-9);
  EXPECT_NEAR(lowered.z(), 0.0, 1e-12);
  EXPECT_GT(lowered.y(), 0.0);
  // At or below the limit, or straight up: unchanged.
  const Eigen::Vector3d low(-0.01, 0.03, 0.01);
  EXPECT_TRUE(BelowElevation(low, up, 0.0).isApprox(low));
  EXPECT_TRUE(BelowElevation(0.03 * up, up, 0.0).isApprox(0.03 * up));
  // The explorer's home turned 0.6 rad about z rises 0.6 rad above the level; with gravity
  // sensed and a limit of 0 it lands on the level, as far from the centre; without gravity
  // sensed, or with the limit at pi / 2, where the turn puts it.
  Ring ring(0.037);
  const GaitGeometry g = ring.Geometry(0.0);
  const SurfaceModel none_felt;
  const Eigen::AngleAxisd tilt(-0.6, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d turned = tilt * ring.home[0];  // home along +y
  EXPECT_TRUE(g.ExplorePoint(0, tilt, ring.view, none_felt, 0.012, 0.0).isApprox(turned));
  ring.view.gravity = -up;
  EXPECT_TRUE(g.ExplorePoint(0, tilt, ring.view, none_felt, 0.012).isApprox(turned));
  const Eigen::Vector3d level = g.ExplorePoint(0, tilt, ring.view, none_felt, 0.012, 0.0);
  EXPECT_NEAR(level.x(), 0.0, 1e-12);
  EXPECT_NEAR(level.norm(), 0.037, 1e-12);
  // The palm sideways (gravity along -z): one finger's home is on top, one below; no limit.
  EXPECT_TRUE(g.HomesLevel(-up));
  ring.view.gravity = -Eigen::Vector3d::UnitZ();
  EXPECT_FALSE(g.HomesLevel(ring.view.gravity));
  const Eigen::AngleAxisd rise(0.6, Eigen::Vector3d::UnitX());  // home +y toward +z
  EXPECT_TRUE(g.ExplorePoint(0, rise, ring.view, none_felt, 0.012, 0.0).isApprox(
      rise * ring.home[0]));
  // Palm down (gravity along +x): the homes are level, but lowered would be away from the palm,
  // where the finger's links wrap the object; no limit.
  ring.view.gravity = up;
  EXPECT_TRUE(g.HomesLevel(ring.view.gravity));
  EXPECT_FALSE(GaitGeometry::PalmBelow(ring.view.gravity));
  EXPECT_TRUE(g.ExplorePoint(0, tilt, ring.view, none_felt, 0.012, 0.0).isApprox(turned));
}

TEST(GaitGeometryTest, ThePalmIsBelowWithinTheAngleAsked) {
  // Gravity 60 deg off pointing into the palm: below it, but not within 45 deg of straight in.
  const Eigen::Vector3d tilted(-std::cos(M_PI / 3), std::sin(M_PI / 3), 0.0);
  EXPECT_TRUE(GaitGeometry::PalmBelow(9.81 * tilted));
  EXPECT_FALSE(GaitGeometry::PalmBelow(9.81 * tilted, std::cos(M_PI / 4)));
  EXPECT_TRUE(GaitGeometry::PalmBelow(-9.81 * Eigen::Vector3d::UnitX(), std::cos(M_PI / 4)));
  EXPECT_FALSE(GaitGeometry::PalmBelow(Eigen::Vector3d::Zero()));  // not sensed
}

TEST(GaitGeometryTest, AnExplorersPointTurnsTowardItsPartnersAntipode) {
  Ring ring(0.037);
  const GaitGeometry g = ring.Geometry(0.0);
  EXPECT_EQ(g.Partner(0), 2);  // homes +y and -y
  EXPECT_EQ(g.Partner(1), 3);
  // The partner (finger 2) has ridden 0.3 rad about z: its antipode lies 0.3 rad from finger
  // 0's home. Turned by at most 0.2 rad the point goes 0.2 rad of the way; by 0.5, all of it.
  const Eigen::AngleAxisd ride(0.3, Eigen::Vector3d::UnitZ());
  ring.view.fingers[2].contact = ride * Eigen::Vector3d(0, -0.025, 0);
  const SurfaceModel none_felt;
  const Eigen::AngleAxisd none(0.0, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d part = g.ExplorePoint(0, none, ring.view, none_felt, 0.012, M_PI / 2, 0.2);
  EXPECT_TRUE(part.isApprox(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) * ring.home[0]));
  const Eigen::Vector3d all = g.ExplorePoint(0, none, ring.view, none_felt, 0.012, M_PI / 2, 0.5);
  EXPECT_TRUE(all.isApprox(ride * ring.home[0]));
  // Not in contact: the gait's point.
  ring.view.fingers[2].in_contact = false;
  EXPECT_TRUE(g.ExplorePoint(0, none, ring.view, none_felt, 0.012, M_PI / 2, 0.5)
                  .isApprox(ring.home[0]));
}

TEST(GaitGeometryTest, AnExplorersPointMovesTowardItsBaseUntilItsTipFacesTheSurface) {
  // A 2.5 cm sphere felt all round; finger 0 stands along +y with its tip's axis pointing down
  // (-z: its base above, like the forefinger over the object's side).
  Ring ring(0.037);
  ring.view.fingers[0].tip_axis = -Eigen::Vector3d::UnitZ();
  const GaitGeometry g = ring.Geometry(0.0);
  SurfaceModel surface;
  for (int i = 0; i < 400; ++i) {
    const double a = 0.37 * i, b = std::asin(2.0 * ((i * 0.618) - std::floor(i * 0.618)) - 1.0);
    const Eigen::Vector3d d(std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b));
    surface.Add(Eigen::Isometry3d::Identity(), 0.025 * d, d, 0.0);
  }
  // Its point 0.3 rad below the equator: the normal there is 90 + 17 deg from its axis.
  const Eigen::Vector3d below =
      0.037 * Eigen::Vector3d(0.0, std::cos(0.3), -std::sin(0.3));
  const double limit = M_PI / 2;  // touch no further round than its side
  const Eigen::Vector3d moved = g.TowardTipFront(0, below, ring.view, surface, 0.012, limit);
  // Moved up to the equator, within one search step (0.05 rad) and the felt normal's error.
  const double elevation = std::asin(moved.z() / moved.norm());
  EXPECT_GE(elevation, -0.06);
  EXPECT_LE(elevation, 0.06);
  EXPECT_NEAR(moved.norm(), 0.037, 1.5e-3);  // on the felt surface, a tip radius out
  // A point already within the angle stays where it is.
  const Eigen::Vector3d above =
      0.037 * Eigen::Vector3d(0.0, std::cos(0.2), std::sin(0.2));
  EXPECT_TRUE(g.TowardTipFront(0, above, ring.view, surface, 0.012, limit).isApprox(above));
}

TEST(GaitGeometryTest, FingersStandAroundThePalmAxisOnly) {
  const GaitGeometry g = Ring(0.025).Geometry(0.03);
  EXPECT_TRUE(g.AroundFingers(Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(g.AroundFingers(-Eigen::Vector3d::UnitX()));
  EXPECT_FALSE(g.AroundFingers(Eigen::Vector3d::UnitY()));
}

TEST(GaitGeometryTest, StepLimitLeavesTheClearanceBetweenNeighbours) {
  // 90 deg apart, each neighbour rides 3 steps toward the explorer: 3 steps + the gap angle of
  // two tips 3 cm apart at 2.5 cm must fit in 90 deg.
  const Ring ring(0.025);
  const double gap = 2.0 * std::asin(0.03 / (2.0 * 0.025));
  EXPECT_NEAR(ring.Geometry(0.03).StepLimit(Eigen::Vector3d::UnitX(), ring.view, 0.0),
              (M_PI / 2 - gap) / 3.0, 1e-12);
  // A larger object leaves larger steps; the smallest step is kept on a tiny one.
  const Ring large(0.05);
  EXPECT_GT(large.Geometry(0.03).StepLimit(Eigen::Vector3d::UnitX(), large.view, 0.0),
            ring.Geometry(0.03).StepLimit(Eigen::Vector3d::UnitX(), ring.view, 0.0));
  const Ring tiny(0.01);
  EXPECT_EQ(tiny.Geometry(0.03).StepLimit(Eigen::Vector3d::UnitX(), tiny.view, 0.04), 0.04);
  // About an axis the fingers do not stand around (two homes at one angle): no limit.
  EXPECT_EQ(ring.Geometry(0.03).StepLimit(Eigen::Vector3d::UnitY(), ring.view, 0.04), 0.0);
}

TEST(GaitGeometryTest, ExplorersPointKeepsClearOfTheFingerBehindIt) {
  const Ring ring(0.025);
  const GaitGeometry g = ring.Geometry(0.03);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  // Finger 1 (at 90 deg) slides back (sign +1: the finger behind it is finger 0, at 0 deg)
  // to 10 deg: within the clearance of finger 0, so moved forward to the gap angle.
  const Eigen::Vector3d target = Eigen::AngleAxisd(0.1745, x) * ring.home[0];
  const Eigen::Vector3d kept = g.KeepClear(1, x, 1.0, 0.0, false, target, ring.view);
  const double gap = 2.0 * std::asin(0.03 / (2.0 * 0.025));
  EXPECT_NEAR(std::atan2(kept.z(), kept.y()), gap, 1e-9);
  EXPECT_NEAR(kept.norm(), 0.025, 1e-12);
  // Far enough ahead already (past the gap angle, 1.29 rad): unchanged.
  const Eigen::Vector3d far = Eigen::AngleAxisd(1.4, x) * ring.home[0];
  EXPECT_TRUE(g.KeepClear(1, x, 1.0, 0.0, false, far, ring.view).isApprox(far));
}

TEST(GaitGeometryTest, DeviationsAndTheStepWithinReach) {
  const Ring ring(0.025);
  const GaitGeometry g = ring.Geometry(0.0, 0.5);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  EXPECT_NEAR(g.Deviation(2, Eigen::AngleAxisd(0.3, x), ring.view), 0.3, 1e-12);
  // Every finger stands on the x axis' circle: a turn about x moves each by its angle; the
  // deviation limit 0.5 stops a 0.8 rad step at the last sample within it (16 samples).
  EXPECT_NEAR(g.StepWithinReach(x, 0.8, -1, ring.view), 0.5, 0.8 / 16);
  EXPECT_LE(g.StepWithinReach(x, 0.8, -1, ring.view), 0.5);
  // About z, the fingers on the y axis (0 and 2) move, those on it (1 and 3) do not.
  EXPECT_EQ(g.FurthestFromHome(Eigen::Vector3d::UnitZ(), 0.3, -1, ring.view), 0);
  EXPECT_EQ(g.FurthestFromHome(Eigen::Vector3d::UnitZ(), 0.3, 0, ring.view), 2);
  // The explorer goes back no further than the limit lets it.
  EXPECT_NEAR(g.LimitBack(1, x, -1.0), -0.5, 1e-12);
  EXPECT_NEAR(g.LimitBack(1, x, -0.2), -0.2, 1e-12);
}

}  // namespace
}  // namespace dmpl
