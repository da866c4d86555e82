#pragma once
// The explorer's next contact, chosen on the surface the fingertips have felt (issue 28): among
// points around the gait's own (GaitGeometry::ExplorePoint), one that
//   (a) the finger reaches with its tip: IK of the hand model within the joints' limits, and
//       its links (not its tip) clear of the felt surface, both where it lands and after the
//       turn it then rides with the object (and, with a bound, its tip landing near its front);
//   (b) leaves a grasp that can carry a load: the weakest, over the palm's six directions, of
//       what the new contact and the other fingers' can hold within the friction the gait
//       plans with (grasp_support.h: SupportAlong);
//   (c) keeps its tip apart from the others'.
// The gait's point stays unless another is clear where it is not, or much better supported:
// on a sphere felt all round the gait is the one it was. Pure: the hand model, the controller's
// view and the felt surface in; a point out.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/controller/grasp_support.h"
#include "components/hand/hand_model.h"
#include "components/kinematics/finger_links.h"
#include "components/kinematics/hand_kinematics.h"
#include "supervisor/supervisor_params.h"
#include "supervisor/supervisor_types.h"
#include "supervisor/surface_model.h"

namespace dmpl {

struct ContactCandidate {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();      // the tip centre's target (palm frame)
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();  // where it touches
  Eigen::Vector3d outward = Eigen::Vector3d::Zero();  // the surface's normal there, unit
  double offset_rad = 0.0;  // from the gait's point, seen from the object's centre
  bool felt = false;        // the surface known there (else: the gait's distance, facing out)
  bool reached = false;     // the tip gets there and after the turn, joints within the margin
  Eigen::VectorXd joints;   // the finger's, there (the IK's answer)
  // The least clearance of the finger's links from the felt surface there and after the turn;
  // infinite where the model knows nothing near them.
  double link_clearance_m = std::numeric_limits<double>::infinity();
  // Round the tip from its front where it lands: the tip's axis at `joints` against the
  // surface's normal there (the simulator's truth of the runs: past ~100 deg the finger's link
  // takes the load within a second on every other landing on an ellipsoid).
  double contact_angle_rad = 0.0;
  double spacing_m = std::numeric_limits<double>::infinity();  // to the nearest other tip
  double support_n = 0.0;   // the weakest of the six directions
};

struct ContactRequest {
  int finger = 0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the gait's tip target (palm frame)
  // The turn the object makes about its centre while the finger rides it before it explores
  // again (identity: none).
  Eigen::AngleAxisd ride{0.0, Eigen::Vector3d::UnitZ()};
  double tip_radius_m = 0.0;
  double min_spacing_m = 0.0;  // between two tips' centres
};

// What a finger that stays in the grip comes to while it rides a turn (ContactChooser::Ride).
struct RideMargins {
  // The least clearance of its links (not its tip) from the felt surface (m; negative: into it);
  // infinite where the model knows nothing near them.
  double link_clearance_m = std::numeric_limits<double>::infinity();
  double limit_margin_rad = std::numeric_limits<double>::infinity();  // of its joints
  bool reached = true;  // its tip follows the contact all the way
};

struct ContactChoice {
  int index = 0;  // into candidates; 0 is the gait's point
  std::string why;
  std::vector<ContactCandidate> candidates;
  const ContactCandidate& chosen() const { return candidates[index]; }
};

// The contacts of the fingers with a sensed point (FingerView::SensesPoint) but `lifted` (-1:
// none) as the grasp-support plan takes them: each at its point, its normal the tip sphere's
// into the object.
std::vector<SupportContact> GripContacts(const ControllerView& view, int lifted);
// What those contacts can hold along the sensed gravity about the sensed centre (SupportAlong),
// N: the grasp's support while finger `lifted` is away.
double SupportWithout(const ControllerView& view, int lifted, const SupportLimits& limits);

class ContactChooser {
 public:
  // `support`: what a grasp is taken to hold (with the friction observed, if it says so).
  ContactChooser(const HandModel& model, ContactChoiceParams params, SupportParams support);

  ContactChoice Choose(const ContactRequest& request, const ControllerView& view,
                       const SurfaceModel& surface) const;
  // The request's own point alone, assessed as Choose assesses it (reach, link clearance there
  // and after the ride; spacing and support left at their defaults).
  ContactCandidate AtPoint(const ContactRequest& request, const ControllerView& view,
                           const SurfaceModel& surface) const;
  // The largest part of `step` (rad, signed) about `axis` through the object's centre, in
  // quarters, that takes no finger in contact but `skip` (-1: none) with its links into the
  // felt surface: further in than the tolerance, or than it stands now if it is already in.
  // `blocking` (may be null): the finger that stops it, -1 when none does.
  double ClearStep(const Eigen::Vector3d& axis, double step, int skip, const ControllerView& view,
                   const SurfaceModel& surface, int* blocking) const;
  // The least clearance of finger `f`'s links (not its tip) from the felt surface in the posture
  // it holds now (m; infinite where the model knows nothing near them).
  double LinkClearanceNow(int f, const ControllerView& view, const SurfaceModel& surface) const;
  // Finger `f` (in contact) riding a turn of `step` (rad, signed) about `axis` through the
  // object's centre, its tip turned with the object: its margins, the least over the turn
  // (sampled in quarters). Whether it can stay in the grip for that turn or must be placed again.
  RideMargins Ride(int f, const Eigen::Vector3d& axis, double step, const ControllerView& view,
                   const SurfaceModel& surface) const;

 private:
  // The candidates' targets: the gait's point, then rings about it (seen from the centre), on
  // the felt surface where it is known.
  std::vector<ContactCandidate> Candidates(const ContactRequest& request,
                                           const ControllerView& view,
                                           const SurfaceModel& surface) const;
  // Fills `c`'s reach and link clearance for finger `f`, from joints `seed`.
  void Assess(int f, const Eigen::VectorXd& seed, const ContactRequest& request,
              const ControllerView& view, const SurfaceModel& surface,
              ContactCandidate* c) const;
  // The least clearance of finger `f`'s links (not its tip) at `q` from the surface with the
  // object at `object`.
  double LinkClearance(int f, const Eigen::VectorXd& q, const SurfaceModel& surface,
                       const Eigen::Isometry3d& object) const;
  double Support(int f, const ContactCandidate& c, const ControllerView& view) const;
  // Of the assessed candidates: the gait's point where it is reached, apart and clear; else the
  // nearest that is (of a ring, the best supported); else the one whose links come least close.
  void Select(const ContactRequest& request, ContactChoice* choice) const;

  ContactChoiceParams params_;
  SupportParams support_;
  std::unique_ptr<HandKinematics> kin_;  // on the heap: the links keep references into it
  std::vector<FingerLinks> links_;
};

}  // namespace dmpl
