#pragma once
// A point kept a margin inside its face, away from the edges that the faces felt around it imply
// (issue 29). The object is convex, so it lies behind the tangent plane of every face a fingertip
// has felt: a flat face ends, at the latest, where it meets another felt face's plane. That
// bounds where a face's edges lie before any explorer has slid over them: on a cube held at four
// faces, the edges between those faces are known from the grasp alone. The gait plans an
// explorer's point on a sphere through its home, which on a flat face lies toward the edges (the
// cube's runs put the ring finger 0.5-9 mm from one). Curved surfaces imply no near edge: a point
// is bounded only on a face felt flat (a fingertip slid 1.2 cm over it with its normal unturned),
// and only by planes whose normals differ from its face's by min_angle_rad or more (1.2 rad). So
// a hexagonal prism's sides (1.05 rad apart) do not bound each other; its ends bound them.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/runtime/params.h"
#include "supervisor/surface_model.h"

namespace dmpl {

// task.face_bounds: the explorer's point kept margin_m inside its face (Gait::Explore).
struct FaceBoundsParams {
  double margin_m = 0.0;       // how far inside its face a point is kept; 0: off
  double min_angle_rad = 1.2;  // a plane bounds a face only if their normals differ this much

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(margin_m), InRange(0, 0.03));
    a->Visit(DMPL_NVP(min_angle_rad), AboveUpTo(0, 1.5707963267948966));
  }
};

// A face felt flat (object frame): a point on it and its outward normal.
struct FlatFace {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

// A face is felt flat when one fingertip slides kSpanM over it within kWindowS while the normal
// under it (from the tip's geometry) stays within kToleranceRad: a surface curved no tighter than
// 12 cm. A sphere's normal turns by travel / R (0.5 rad over 1.2 cm on a 2.5 cm sphere); within
// the window the object pose estimate's slow drift moves the points by little. Pure: no LCM.
class FlatFaceDetector {
 public:
  static constexpr double kSpanM = 0.012;
  static constexpr double kToleranceRad = 0.1;
  static constexpr double kWindowS = 1.5;

  // One contact of one sliding finger, in time order (object frame): the face, once, when its
  // slide over it reaches the span.
  std::optional<FlatFace> Add(double time_s, const Eigen::Vector3d& point,
                              const Eigen::Vector3d& normal);
  void Reset() { start_.reset(); }  // the slide ended

 private:
  struct Start {
    double time_s;
    Eigen::Vector3d point, normal;
    bool reported;
  };
  std::optional<Start> start_;
};

// Whether a fingertip centred at `tip` (object frame) would touch one of the faces `flat`: the
// felt tangent plane it lies furthest outside of is one of them (a sphere has none).
bool MeetsFlatFace(const Eigen::Vector3d& tip, const SurfaceModel& surface,
                   const std::vector<FlatFace>& flat);

// The fingertip's centre `tip` (object frame) moved along the face it would touch until its
// contact there lies at least params.margin_m from every felt tangent plane that bounds the face
// (normals at least min_angle_rad apart); unchanged where none is nearer, or where the contact
// lies past any felt plane turned from the face's (the gait sends it round to the next face: a
// hexagonal prism's next side is turned 1.05 rad, under min_angle_rad). The face is the felt
// plane the tip lies furthest outside of, and it must be one of the faces `flat` (a sphere's
// tangent planes imply no edge). `moved_m`, if given, gets how far the tip was moved.
Eigen::Vector3d KeepInsideFace(const Eigen::Vector3d& tip, const SurfaceModel& surface,
                               const std::vector<FlatFace>& flat, const FaceBoundsParams& params,
                               double* moved_m = nullptr);

}  // namespace dmpl
