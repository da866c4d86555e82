#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include <Eigen/Geometry>

#include "components/hand/testing/project_hand.h"
#include "sim_process/sim/convex_object.h"
#include "sim_process/sim/hand_sim.h"

namespace dmpl {
namespace {

std::vector<Eigen::Vector3d> CubePoints(double a) {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 8; ++i) p.emplace_back((i & 1 ? a : -a) / 2, (i & 2 ? a : -a) / 2, (i & 4 ? a : -a) / 2);
  return p;
}

std::string TempFile(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(ConvexObjectTest, ACubesHullHasItsVolumeAndInertia) {
  const ConvexHull hull = HullOf(CubePoints(0.05));
  EXPECT_EQ(hull.vertices.size(), 8u);
  EXPECT_EQ(hull.triangles.size(), 12u);  // six squares, two triangles each
  const MassProperties m = MassOf(hull, 0.05);
  EXPECT_NEAR(m.volume, 1.25e-4, 1e-12);
  EXPECT_LT(m.centroid.norm(), 1e-12);
  const double i = 0.05 * (2 * 0.05 * 0.05) / 12;
  EXPECT_TRUE(m.inertia.isApprox(i * Eigen::Matrix3d::Identity(), 1e-9)) << m.inertia;
}

TEST(ConvexObjectTest, AHexagonalPrismMatchesItsAnalyticMoments) {
  const double r = 0.025, l = 0.06, mass = 0.08;
  const MassProperties m = MassOf(HullOf(PrismPoints(6, r, l)), mass);
  EXPECT_NEAR(m.volume, 1.5 * std::sqrt(3.0) * r * r * l, 1e-12);
  // A regular hexagon's polar moment is 5 R^2 / 12 per unit mass.
  EXPECT_NEAR(m.inertia(2, 2), mass * 5 * r * r / 12, 1e-12);
  EXPECT_NEAR(m.inertia(0, 0), mass * (5 * r * r / 24 + l * l / 12), 1e-12);
  EXPECT_NEAR(m.inertia(0, 1), 0.0, 1e-15);
}

TEST(ConvexObjectTest, AMovedAndTurnedShapeHasItsCentroidThereAndItsInertiaTurned) {
  const Eigen::Isometry3d pose = Eigen::Translation3d(0.01, -0.02, 0.03) *
                                 Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  std::vector<Eigen::Vector3d> points = PrismPoints(5, 0.02, 0.07);
  const MassProperties at_origin = MassOf(HullOf(points), 0.1);
  for (auto& p : points) p = pose * p;
  const MassProperties moved = MassOf(HullOf(points), 0.1);
  EXPECT_TRUE(moved.centroid.isApprox(pose.translation(), 1e-9));
  EXPECT_TRUE(moved.inertia.isApprox(pose.linear() * at_origin.inertia * pose.linear().transpose(),
                                     1e-9));
}

TEST(ConvexObjectTest, MeshFilesReadAsObjAsciiStlAndBinaryStl) {
  const std::string obj = TempFile("cube.obj",
                                   "# a cube\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                   "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nf 1 2 3\n");
  const Mesh cube = ReadMesh(obj);
  EXPECT_EQ(cube.points.size(), 8u);
  ASSERT_EQ(cube.triangles.size(), 1u);
  EXPECT_EQ(cube.triangles[0], (std::array<int, 3>{0, 1, 2}));
  const std::string ascii = TempFile("tet.stl",
                                     "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\n"
                                     "vertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
                                     "facet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                     "vertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n");
  EXPECT_EQ(ReadMesh(ascii).points.size(), 6u);
  EXPECT_EQ(ReadMesh(ascii).triangles.size(), 2u);
  // Polygons (a fan), corners with texture and normal indices, negative indices.
  const Mesh quad = ReadMesh(TempFile("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                                  "f 1/1/1 2/2/2 3/3/3 -1\n"));
  ASSERT_EQ(quad.triangles.size(), 2u);
  EXPECT_EQ(quad.triangles[1], (std::array<int, 3>{0, 2, 3}));
  std::string binary(80, ' ');
  const uint32_t count = 1;
  binary.append(reinterpret_cast<const char*>(&count), 4);
  const float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  binary.append(reinterpret_cast<const char*>(tri), sizeof(tri));
  binary.append(2, '\0');
  const auto points = ReadMesh(TempFile("tri.stl", binary)).points;
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[1], Eigen::Vector3d(1, 0, 0));
}

// Each error says what is wrong with which file.
TEST(ConvexObjectTest, BadMeshFilesSayWhatIsWrong) {
  auto error_of = [](const std::string& path) -> std::string {
    try {
      HullOf(ReadMesh(path).points);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of("/no/such.obj").find("no such mesh file '/no/such.obj'"), std::string::npos);
  EXPECT_NE(error_of(TempFile("empty.obj", "# nothing\n")).find("has no vertices"),
            std::string::npos);
  EXPECT_NE(error_of(TempFile("bad.obj", "v 1 2\n")).find("bad.obj:1: a vertex needs three"),
            std::string::npos);
  EXPECT_NE(error_of(TempFile("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n")).find("plane"),
            std::string::npos);
  EXPECT_NE(error_of(TempFile("short.stl", "xyz")).find("shorter than its header"),
            std::string::npos);
  EXPECT_NE(error_of(TempFile("mesh.ply", "ply")).find("not .obj or .stl"), std::string::npos);
  EXPECT_NE(error_of(TempFile("face.obj", "v 0 0 0\nf 1 2 3\n")).find("face.obj:2: a face names vertex 2"),
            std::string::npos);
}

TEST(ConvexObjectTest, ANonConvexMeshIsFoundByItsFacesInsideTheHull) {
  // An L extruded 1 cm: the inner corner's two walls lie inside the hull of the whole.
  const std::vector<std::pair<double, double>> outline = {
      {0, 0}, {0.04, 0}, {0.04, 0.01}, {0.01, 0.01}, {0.01, 0.04}, {0, 0.04}};
  Mesh l_shape;
  for (double z : {0.0, 0.01}) {
    for (const auto& [x, y] : outline) l_shape.points.emplace_back(x, y, z);
  }
  for (int k = 0; k < 6; ++k) {  // the side walls
    const int a = k, b = (k + 1) % 6;
    l_shape.triangles.push_back({a, b, b + 6});
    l_shape.triangles.push_back({a, b + 6, a + 6});
  }
  const ConvexHull hull = HullOf(l_shape.points);
  // The inner walls' triangles have their centroids inside the hull, more than 3 mm from its
  // nearest face (the outer walls' lie on it).
  EXPECT_GT(DeepestTriangle(l_shape, hull), 0.003);
  // A cube's faces are its hull's.
  const ConvexHull cube_hull = HullOf(CubePoints(0.05));
  const Mesh cube{cube_hull.vertices, cube_hull.triangles};
  EXPECT_LT(DeepestTriangle(cube, cube_hull), 1e-12);
}

TEST(ConvexObjectTest, TheShippedMeshesAreConvexAndTheSimulatorTakesThem) {
  const HandModel model = testing::LoadHand();
  for (const char* file : {"configs/objects/egg.obj", "configs/objects/pebble.stl"}) {
    const Mesh mesh = ReadMesh(std::string(DMPL_SOURCE_DIR "/") + file);
    const ConvexHull hull = HullOf(mesh.points);
    EXPECT_LT(DeepestTriangle(mesh, hull), 1e-6) << file;
    ObjectParams object;
    object.shape = "mesh";
    object.mesh = std::string(DMPL_SOURCE_DIR "/") + file;
    object.position = {0.3, 0.5, 0.5};
    object.rpy = {0.3, -0.2, 0.5};
    const ObjectBody body = MakeObjectBody(object, "test");
    // The inertia's principal frame at the hull's centroid; its moments positive.
    EXPECT_TRUE(body.principal.translation().isApprox(MassOf(hull, 0.05).centroid, 1e-9));
    EXPECT_GT(body.inertia.minCoeff(), 0.0);
    // The pose reported is the file's frame where the config puts it.
    HandSim hand(model, SimParams{}, object, "test");
    const Eigen::Isometry3d pose = hand.object().pose;
    EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(0.3, 0.5, 0.5), 1e-9)) << file;
    const Eigen::Matrix3d rpy = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
    EXPECT_TRUE(pose.linear().isApprox(rpy, 1e-9)) << file;
  }
}

TEST(ConvexObjectTest, MeshConfigErrorsNameTheKey) {
  const HandModel model = testing::LoadHand();
  auto error_of = [&](const ObjectParams& o) -> std::string {
    try {
      HandSim(model, SimParams{}, o, "objects.yaml");
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  ObjectParams o;
  o.shape = "mesh";
  EXPECT_NE(error_of(o).find("objects.yaml: key 'object.mesh': a mesh object needs its file"),
            std::string::npos) << error_of(o);
  o.mesh = "/no/such.stl";
  EXPECT_NE(error_of(o).find("key 'object.mesh': no such mesh file"), std::string::npos);
  o.mesh = TempFile("l.obj", "v 0 0 0\nv 0.04 0 0\nv 0.04 0.01 0\nv 0.01 0.01 0\nv 0.01 0.04 0\n"
                             "v 0 0.04 0\nv 0 0 0.01\nv 0.04 0 0.01\nv 0.04 0.01 0.01\n"
                             "v 0.01 0.01 0.01\nv 0.01 0.04 0.01\nv 0 0.04 0.01\n"
                             "f 3 4 10 9\nf 4 5 11 10\n");  // the inner corner's walls
  EXPECT_NE(error_of(o).find("not convex"), std::string::npos) << error_of(o);
  o.mesh = std::string(DMPL_SOURCE_DIR) + "/configs/objects/egg.obj";
  o.scale = 1000.0;  // a file in metres read as millimetres
  EXPECT_NE(error_of(o).find("object.scale: its unit?"), std::string::npos) << error_of(o);
  ObjectParams prism;
  prism.shape = "prism";
  prism.sides = 2;
  EXPECT_NE(error_of(prism).find("object.sides"), std::string::npos) << error_of(prism);
}

}  // namespace
}  // namespace dmpl
