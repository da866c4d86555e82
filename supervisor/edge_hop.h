#pragma once
// An explorer whose point lies past an edge the fingertips have felt steps over it (issue 29):
// eased to an explorer's force where it stands, lifted off its face, moved over its point and
// brought in to it as any explorer (a guarded approach: toward the object until it touches,
// then along the surface). Slid round the edge instead, its tip rolls over the corner with the
// distal link along the face it leaves. This file says when: the explorer's way crosses a felt
// edge. The gait (gait.h) moves the finger.
#include <vector>

#include <Eigen/Geometry>

#include "supervisor/edge_detector.h"

namespace dmpl {

// Whether the way over the surface from `from` to `to` (points in the object frame, whose
// origin is the object's centre) crosses the felt `edge` (object frame): the plane through the
// centre and the edge's line (its direction: across the two faces' normals) has them on its two
// sides, and the arc between their directions meets that plane on the edge's side of the centre,
// no further than `reach_m` along the line from where the edge was felt (an edge felt once is
// taken to run on that far; the shapes the hand holds are a few cm across).
bool CrossesEdge(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const Edge& edge,
                 double reach_m);

// The first of `edges` that the way from `from` to `to` crosses (CrossesEdge), or -1.
int EdgeOnTheWay(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                 const std::vector<Edge>& edges, double reach_m);

}  // namespace dmpl
