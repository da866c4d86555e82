#include "supervisor/edge_hop.h"

#include <cmath>

namespace dmpl {

bool CrossesEdge(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const Edge& edge,
                 double reach_m) {
  const Eigen::Vector3d along = edge.normal_before.cross(edge.normal_after);
  if (along.norm() < 1e-6 || from.norm() < 1e-9 || to.norm() < 1e-9) return false;
  const Eigen::Vector3d e = along.normalized();
  // The line's point nearest the centre, and the plane through the centre and the line.
  const Eigen::Vector3d nearest = edge.point - edge.point.dot(e) * e;
  if (nearest.norm() < 1e-6) return false;  // a line through the centre is no edge of a convex shape
  const Eigen::Vector3d side = nearest.cross(e).normalized();
  const Eigen::Vector3d a = from.normalized();
  const Eigen::Vector3d b = to.normalized();
  const double sa = a.dot(side);
  const double sb = b.dot(side);
  if (sa * sb >= 0.0) return false;  // both on one side (or on the plane)
  // Where the arc from a to b meets the plane: a positive mix of the two with no `side` part.
  const Eigen::Vector3d u = (std::abs(sb) * a + std::abs(sa) * b).normalized();
  const double out = u.dot(nearest.normalized());
  if (out <= 1e-6) return false;  // the plane is met across the centre from the edge
  // The point of the line seen along u, against where the edge was felt.
  const double at = nearest.norm() * u.dot(e) / out;
  return std::abs(at - edge.point.dot(e)) <= reach_m;
}

int EdgeOnTheWay(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                 const std::vector<Edge>& edges, double reach_m) {
  for (size_t i = 0; i < edges.size(); ++i) {
    if (CrossesEdge(from, to, edges[i], reach_m)) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace dmpl
