#pragma once
// Objects given by points (issue 29): a regular prism and a convex mesh a user brings (an OBJ or
// STL file), as their convex hull, with the mass properties of the hull at uniform density.
// Pure: no Bullet types in the interface (the hull is computed by Bullet's
// btConvexHullComputer inside).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace dmpl {

struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside
};

// Volume, centre of mass and inertia (about the centre of mass, in the points' frame) of a solid
// hull of uniform density and the given mass.
struct MassProperties {
  double volume = 0.0;  // m^3
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // kg m^2
};

// A regular n-gon of circumradius `radius` (a vertex on +x) extruded along z, centred.
std::vector<Eigen::Vector3d> PrismPoints(int sides, double radius, double length);

// A mesh file's vertices and triangles (a polygon's fan; an OBJ may give vertices only).
struct Mesh {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
};

// A mesh file: Wavefront OBJ ("v x y z" and "f a b c ..." lines) or STL (ASCII or binary), by
// its extension. Throws std::runtime_error saying what is wrong (no such file, no vertices, a
// line that does not parse, a face naming a vertex that is not there).
Mesh ReadMesh(const std::string& path);

// The convex hull of `points`. Throws std::runtime_error when they span no volume (fewer than
// four points, or all in a plane).
ConvexHull HullOf(const std::vector<Eigen::Vector3d>& points);

// How far the deepest of `points` lies inside `hull` (0 when every point is on its surface).
double DeepestInside(const ConvexHull& hull, const std::vector<Eigen::Vector3d>& points);

// How far inside its own convex hull the deepest of a mesh's triangles lies (by its centroid):
// a convex mesh's triangles all lie on its hull; a dent's do not.
double DeepestTriangle(const Mesh& mesh, const ConvexHull& hull);

MassProperties MassOf(const ConvexHull& hull, double mass);

}  // namespace dmpl
