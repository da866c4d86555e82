#pragma once
// Which touching fingers turn their tips' fronts toward the surface (task.face_surface): on a
// cube's side faces the fore and ring fingers touch with the sides of their tips, their distal
// links 2.5-3.1 mm off, and a few degrees of tilt lay a link on the face; the redundancy of
// their tips' position can turn them to touch nearer their fronts. On a sphere the links stand
// 4.2-4.6 mm off, and the posture is left as it is. So a finger is asked only where the hand model
// puts its links near the felt surface: a grip finger where it stands, the explorer at its point.
// Pure: the hand model (through the chooser), the controller's view and the felt surface in.
#include "components/controller/controller_types.h"
#include "supervisor/contact_chooser.h"
#include "supervisor/face_bounds.h"
#include "supervisor/supervisor_params.h"
#include "supervisor/supervisor_types.h"
#include "supervisor/surface_model.h"

namespace dmpl {

// Sets each finger's FingerTask::face_surface in `task`: a finger that senses its contact point
// (FingerView::SensesPoint), gripping (params.grip_fingers) or exploring toward a target, whose
// links the chooser's hand model puts less than params.clearance_m off the felt surface, and
// with params.flat_faces_only whose tip (the explorer's at its target) meets one of the faces
// `flat`. The others: false.
void AskToFaceSurface(const ContactChooser& chooser, const FaceSurfaceParams& params,
                      const ControllerView& view, const SurfaceModel& surface,
                      const std::vector<FlatFace>& flat, double tip_radius_m, TaskInput* task);

}  // namespace dmpl
