#include "supervisor/edge_hop.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dmpl {
namespace {

// The 5 cm cube's edge along y between its +x and +z faces, felt where y = 0.
Edge CubeEdge() {
  Edge e;
  e.point = Eigen::Vector3d(0.025, 0.0, 0.025);
  e.normal_before = Eigen::Vector3d::UnitX();
  e.normal_after = Eigen::Vector3d::UnitZ();
  e.angle_rad = M_PI / 2;
  return e;
}

TEST(EdgeHopTest, AWayFromOneFaceToTheNextCrossesTheEdgeBetween) {
  const Edge e = CubeEdge();
  EXPECT_TRUE(CrossesEdge({0.025, 0.0, 0.0}, {0.0, 0.0, 0.025}, e, 0.03));
  EXPECT_TRUE(CrossesEdge({0.0, 0.0, 0.025}, {0.025, 0.0, 0.0}, e, 0.03));  // either way
  // Near the edge on both sides, 2 cm along it from where it was felt.
  EXPECT_TRUE(CrossesEdge({0.025, 0.02, 0.02}, {0.02, 0.02, 0.025}, e, 0.03));
}

TEST(EdgeHopTest, AWayOnOneFaceCrossesNoEdge) {
  const Edge e = CubeEdge();
  EXPECT_FALSE(CrossesEdge({0.025, 0.0, 0.0}, {0.025, 0.01, 0.02}, e, 0.03));
  EXPECT_FALSE(CrossesEdge({0.0, 0.0, 0.025}, {-0.02, 0.01, 0.025}, e, 0.03));
}

TEST(EdgeHopTest, TheEdgesLineSeenAcrossTheCentreIsNoEdge) {
  // From the -x face to the -z face: the plane through the centre and the edge separates them,
  // but on the far side of the centre (the cube's opposite edge, not this one).
  EXPECT_FALSE(CrossesEdge({-0.025, 0.0, 0.0}, {0.0, 0.0, -0.025}, CubeEdge(), 0.03));
}

TEST(EdgeHopTest, AnEdgeFeltFarAlongItsLineIsNotTakenToRunThatFar) {
  // Crossing the edge 4.4 cm along it from where it was felt (from 5 mm either side of it).
  const Eigen::Vector3d from(0.025, 0.04, 0.02), to(0.02, 0.04, 0.025);
  EXPECT_FALSE(CrossesEdge(from, to, CubeEdge(), 0.03));
  EXPECT_TRUE(CrossesEdge(from, to, CubeEdge(), 0.05));
}

TEST(EdgeHopTest, AHexagonalPrismsEdgeBetweenFacesAt60Degrees) {
  // Faces at 0 and 60 deg about z, apothem 2.5 cm: their edge at 30 deg.
  const double apothem = 0.025;
  const Eigen::Vector3d n0 = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d n1 = Eigen::AngleAxisd(M_PI / 3, Eigen::Vector3d::UnitZ()) * n0;
  Edge e;
  e.normal_before = n0;
  e.normal_after = n1;
  e.point = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()) * n0 *
            (apothem / std::cos(M_PI / 6));
  EXPECT_TRUE(CrossesEdge(apothem * n0, apothem * n1, e, 0.03));
  // Both points on the first face, either side of its centre.
  const Eigen::Vector3d along_face = Eigen::Vector3d::UnitY();
  EXPECT_FALSE(CrossesEdge(apothem * n0 - 0.01 * along_face, apothem * n0 + 0.01 * along_face, e,
                           0.03));
}

TEST(EdgeHopTest, TheFirstEdgeOnTheWayOfSeveral) {
  Edge other = CubeEdge();
  other.point = Eigen::Vector3d(-0.025, 0.0, 0.025);  // the -x / +z edge
  other.normal_before = -Eigen::Vector3d::UnitX();
  const std::vector<Edge> edges = {other, CubeEdge()};
  EXPECT_EQ(EdgeOnTheWay({0.025, 0.0, 0.0}, {0.0, 0.0, 0.025}, edges, 0.03), 1);
  EXPECT_EQ(EdgeOnTheWay({0.025, 0.0, 0.0}, {0.025, 0.01, 0.0}, edges, 0.03), -1);
  EXPECT_EQ(EdgeOnTheWay({0.025, 0.0, 0.0}, {0.0, 0.0, 0.025}, {}, 0.03), -1);
}

TEST(EdgeHopTest, DegenerateInputCrossesNothing) {
  Edge flat = CubeEdge();
  flat.normal_after = flat.normal_before;  // no edge: its line has no direction
  EXPECT_FALSE(CrossesEdge({0.025, 0.0, 0.0}, {0.0, 0.0, 0.025}, flat, 0.03));
  EXPECT_FALSE(CrossesEdge(Eigen::Vector3d::Zero(), {0.0, 0.0, 0.025}, CubeEdge(), 0.03));
}

}  // namespace
}  // namespace dmpl
