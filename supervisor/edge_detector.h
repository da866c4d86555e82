#pragma once
// Edges by touch (issue 29): a fingertip sliding or rolling over an edge keeps its contact on
// the edge while the surface normal under it turns by the angle between the two faces; on a
// face the normal does not turn, and on a curved surface of radius R it turns by travel / R.
// So an edge is a turn of the normal by more than min_turn_rad while the contact point travels
// less than max_travel_m: a surface curved tighter than max_travel_m / min_turn_rad (8 mm by
// default: tighter than any object the hand holds, looser than any edge). Normals come from the
// tip's geometry (contact point minus tip centre), so the object pose's noise does not enter
// them; the points do carry it, in the object frame, and make the travel look longer, never a
// turn: the pose noise can hide an edge, not make one.
// Pure: no LCM.
#include <deque>
#include <optional>

#include <Eigen/Core>

namespace dmpl {

struct EdgeDetectorParams {
  double min_turn_rad = 0.5;     // a 90 deg edge turns 1.57, a hexagonal prism's 1.05
  double max_travel_m = 0.004;
  double window_s = 0.5;         // how far back a turn is looked for (a tip rolls round an
                                 // edge at speed / r_tip: 0.5 rad in 0.3 s at 2 cm/s)
};

struct Edge {
  double time_s = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();          // on the edge (the caller's frame)
  Eigen::Vector3d normal_before = Eigen::Vector3d::Zero();  // the face left
  Eigen::Vector3d normal_after = Eigen::Vector3d::Zero();   // the face reached
  double angle_rad = 0.0;                                   // between the two normals
  // The tip still rolling round the edge found last: the same edge, turned further (its
  // normal_before kept, normal_after and angle updated).
  bool continues = false;
};

class EdgeDetector {
 public:
  explicit EdgeDetector(EdgeDetectorParams params = {}) : params_(params) {}

  // One contact of one finger, in time order: its point and outward unit normal. An edge when
  // the normal has turned over one since the last; while the tip goes on rolling round it, the
  // same edge again (Edge::continues) as its angle grows.
  std::optional<Edge> Add(double time_s, const Eigen::Vector3d& point,
                          const Eigen::Vector3d& normal);
  void Reset() {  // the contact ended: a new one starts a new trace
    trace_.clear();
    last_.reset();
  }

 private:
  struct Sample {
    double time_s;
    Eigen::Vector3d point, normal;
  };
  EdgeDetectorParams params_;
  std::deque<Sample> trace_;
  std::optional<Edge> last_;  // the edge found last, while the tip may still roll round it
};

}  // namespace dmpl
