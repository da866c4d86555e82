#include "supervisor/face_surface.h"

#include <limits>

namespace dmpl {

void AskToFaceSurface(const ContactChooser& chooser, const FaceSurfaceParams& params,
                      const ControllerView& view, const SurfaceModel& surface,
                      const std::vector<FlatFace>& flat, double tip_radius_m, TaskInput* task) {
  const Eigen::Isometry3d to_object = view.object.inverse();
  for (int f = 0; f < static_cast<int>(task->fingers.size()); ++f) {
    FingerTask& t = task->fingers[f];
    t.face_surface = false;
    if (!view.fingers[f].SensesPoint()) continue;
    const bool explores = t.role == Role::kExplore && t.has_target;
    const Eigen::Vector3d tip = explores ? t.target : view.fingers[f].tip;
    if (params.flat_faces_only && !MeetsFlatFace(to_object * tip, surface, flat)) continue;
    double clearance = std::numeric_limits<double>::infinity();
    if (explores) {
      ContactRequest request;  // where it lands, no ride
      request.finger = f;
      request.point = t.target;
      request.tip_radius_m = tip_radius_m;
      clearance = chooser.AtPoint(request, view, surface).link_clearance_m;
    } else if (t.role == Role::kGrip && params.grip_fingers) {
      clearance = chooser.LinkClearanceNow(f, view, surface);  // where it stands
    }
    t.face_surface = clearance < params.clearance_m;
  }
}

}  // namespace dmpl
