#include "sim_process/sim/convex_object.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>
#include <LinearMath/btConvexHullComputer.h>

namespace dmpl {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

Eigen::Vector3d ParsePoint(std::istream& words, const std::string& where) {
  Eigen::Vector3d p;
  if (!(words >> p.x() >> p.y() >> p.z()) || !p.allFinite()) {
    throw std::runtime_error(where + ": a vertex needs three numbers");
  }
  return p;
}

Mesh ReadObj(std::istream& in, const std::string& path) {
  Mesh mesh;
  std::vector<std::vector<int>> faces;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string where = path + ":" + std::to_string(n);
    std::istringstream words(line);
    std::string tag;
    if (!(words >> tag)) continue;
    if (tag == "v") mesh.points.push_back(ParsePoint(words, where));
    if (tag != "f") continue;
    // "f 1 2 3", "f 1/1/1 2/2/2 ...": the vertex is the first number; negative counts back.
    std::vector<int> face;
    for (std::string corner; words >> corner;) {
      int k = 0;
      try {
        k = std::stoi(corner);
      } catch (const std::exception&) {
        throw std::runtime_error(where + ": a face corner '" + corner + "' is not a number");
      }
      k = k < 0 ? static_cast<int>(mesh.points.size()) + k : k - 1;
      if (k < 0 || k >= static_cast<int>(mesh.points.size())) {
        throw std::runtime_error(where + ": a face names vertex " + corner + ", not defined");
      }
      face.push_back(k);
    }
    for (size_t i = 1; i + 1 < face.size(); ++i) {
      mesh.triangles.push_back({face[0], face[i], face[i + 1]});
    }
  }
  return mesh;
}

Mesh ReadAsciiStl(std::istream& in, const std::string& path) {
  Mesh mesh;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::istringstream words(line);
    std::string tag;
    if (!(words >> tag) || Lower(tag) != "vertex") continue;
    mesh.points.push_back(ParsePoint(words, path + ":" + std::to_string(n)));
  }
  if (mesh.points.size() % 3 != 0) {
    throw std::runtime_error(path + ": " + std::to_string(mesh.points.size()) +
                             " vertices do not make whole triangles");
  }
  for (int k = 0; k + 2 < static_cast<int>(mesh.points.size()); k += 3) {
    mesh.triangles.push_back({k, k + 1, k + 2});
  }
  return mesh;
}

// 80 bytes of header, a little-endian uint32 count, then 50 bytes per triangle (normal, three
// vertices as float32, two attribute bytes).
Mesh ReadBinaryStl(const std::string& bytes, const std::string& path) {
  if (bytes.size() < 84) throw std::runtime_error(path + ": a binary STL shorter than its header");
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() != 84 + 50ull * count) {
    throw std::runtime_error(path + ": a binary STL of " + std::to_string(count) +
                             " triangles must be " + std::to_string(84 + 50ull * count) +
                             " bytes, not " + std::to_string(bytes.size()));
  }
  Mesh mesh;
  for (uint32_t t = 0; t < count; ++t) {
    const char* tri = bytes.data() + 84 + 50ull * t + 12;
    const int k = static_cast<int>(mesh.points.size());
    for (int v = 0; v < 3; ++v) {
      float xyz[3];
      std::memcpy(xyz, tri + 12 * v, 12);
      const Eigen::Vector3d p(xyz[0], xyz[1], xyz[2]);
      if (!p.allFinite()) throw std::runtime_error(path + ": a vertex that is not a number");
      mesh.points.push_back(p);
    }
    mesh.triangles.push_back({k, k + 1, k + 2});
  }
  return mesh;
}

}  // namespace

std::vector<Eigen::Vector3d> PrismPoints(int sides, double radius, double length) {
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < sides; ++k) {
    const double a = 2.0 * M_PI * k / sides;
    for (double z : {-length / 2, length / 2}) {
      points.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
  }
  return points;
}

Mesh ReadMesh(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("no such mesh file '" + path + "'");
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string ext = Lower(path.substr(path.find_last_of('.') + 1));
  Mesh mesh;
  std::istringstream text(bytes);
  if (ext == "obj") {
    mesh = ReadObj(text, path);
  } else if (ext == "stl") {
    // An ASCII STL begins with "solid" and names its vertices; some binary ones begin with
    // "solid" too, so the words decide.
    const bool ascii = bytes.compare(0, 5, "solid") == 0 && bytes.find("vertex") != std::string::npos;
    mesh = ascii ? ReadAsciiStl(text, path) : ReadBinaryStl(bytes, path);
  } else {
    throw std::runtime_error("mesh file '" + path + "': not .obj or .stl");
  }
  if (mesh.points.empty()) throw std::runtime_error("mesh file '" + path + "' has no vertices");
  return mesh;
}

ConvexHull HullOf(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) throw std::runtime_error("fewer than 4 points span no volume");
  std::vector<double> coords;
  for (const auto& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  btConvexHullComputer computer;
  computer.compute(coords.data(), 3 * sizeof(double), static_cast<int>(points.size()), 0, 0);
  // The computer rounds to a grid of its own; the hull's vertices are the input's, exactly.
  ConvexHull hull;
  for (int i = 0; i < computer.vertices.size(); ++i) {
    hull.vertices.push_back(points[computer.original_vertex_index[i]]);
  }
  // Each face is a convex polygon: a fan of triangles from its first vertex.
  for (int f = 0; f < computer.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &computer.edges[computer.faces[f]];
    const int a = first->getSourceVertex();
    for (const btConvexHullComputer::Edge* e = first->getNextEdgeOfFace(); e != first;
         e = e->getNextEdgeOfFace()) {
      const int b = e->getSourceVertex(), c = e->getTargetVertex();
      if (c != a) hull.triangles.push_back({a, b, c});
    }
  }
  if (MassOf(hull, 1.0).volume <= 0) throw std::runtime_error("the points lie in a plane");
  return hull;
}

double DeepestInside(const ConvexHull& hull, const std::vector<Eigen::Vector3d>& points) {
  double deepest = 0.0;
  for (const auto& p : points) {
    // Inside a convex hull every face's plane has the point behind it; its depth is the
    // distance to the nearest plane.
    double depth = std::numeric_limits<double>::infinity();
    for (const auto& t : hull.triangles) {
      const Eigen::Vector3d& a = hull.vertices[t[0]];
      const Eigen::Vector3d n =
          (hull.vertices[t[1]] - a).cross(hull.vertices[t[2]] - a).normalized();
      depth = std::min(depth, n.dot(a - p));
    }
    deepest = std::max(deepest, depth);
  }
  return deepest;
}

double DeepestTriangle(const Mesh& mesh, const ConvexHull& hull) {
  std::vector<Eigen::Vector3d> centroids;
  for (const auto& t : mesh.triangles) {
    centroids.push_back((mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]]) / 3.0);
  }
  return DeepestInside(hull, centroids);
}

MassProperties MassOf(const ConvexHull& hull, double mass) {
  // Tetrahedra from a point inside (the mean vertex) to each triangle: volume, first and second
  // moments, summed; then moved to the centroid.
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  for (const auto& v : hull.vertices) o += v;
  o /= std::max<size_t>(1, hull.vertices.size());
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T, x from o
  for (const auto& t : hull.triangles) {
    Eigen::Matrix3d a;
    a << hull.vertices[t[0]] - o, hull.vertices[t[1]] - o, hull.vertices[t[2]] - o;
    const double v = a.determinant() / 6.0;
    volume += v;
    first += v * (a.col(0) + a.col(1) + a.col(2)) / 4.0;
    // The covariance of the tetrahedron (0, a, b, c): det / 120 * A S A^T, S = 1 + I.
    const Eigen::Matrix3d s = Eigen::Matrix3d::Ones() + Eigen::Matrix3d::Identity();
    second += a.determinant() / 120.0 * a * s * a.transpose();
  }
  MassProperties m;
  m.volume = volume;
  if (volume <= 0) return m;
  const Eigen::Vector3d d = first / volume;
  m.centroid = o + d;
  const Eigen::Matrix3d about_centroid = (second - volume * d * d.transpose()) * (mass / volume);
  m.inertia = about_centroid.trace() * Eigen::Matrix3d::Identity() - about_centroid;
  return m;
}

}  // namespace dmpl
