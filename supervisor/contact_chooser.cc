#include "supervisor/contact_chooser.h"

#include <algorithm>
#include <cmath>

#include "components/ik/finger_ik.h"
#include "components/runtime/check.h"
#include "supervisor/link_clearance.h"

namespace dmpl {

namespace {

// The chooser's IK: a full solve from a seed (the node's IK moves a little each tick instead).
IkParams PlanningIk() {
  IkParams p;
  p.tolerance_m = 1e-4;
  p.max_iterations = 100;
  p.restarts = 2;
  return p;
}

// The finger's joints now: the IK's answer for its sensed tip whose redundancy turns the tip's
// axis to the sensed one (the hand's posture, which the supervisor does not read), as the IK
// node turns it, a step a solve.
Eigen::VectorXd PostureNow(const FingerKinematics& finger, const FingerView& view) {
  IkParams p = PlanningIk();
  p.nullspace_gain = 0.0;
  p.approach_gain = 1.0;
  constexpr int kTurns = 40;
  Eigen::VectorXd q = (finger.lower() + finger.upper()) / 2.0;
  for (int i = 0; i < kTurns; ++i) q = SolveFingerIk(finger, q, view.tip, p, view.tip_axis).q;
  return q;
}

// How near its limits a joint vector comes (rad; negative: beyond).
double LimitMargin(const FingerKinematics& finger, const Eigen::VectorXd& q) {
  return std::min((q - finger.lower()).minCoeff(), (finger.upper() - q).minCoeff());
}

// The object's pose after `turn` about its own centre (the centre stays, the contacts ride).
Eigen::Isometry3d TurnedInPlace(const Eigen::Isometry3d& object, const Eigen::AngleAxisd& turn) {
  Eigen::Isometry3d turned = object;
  turned.linear() = turn.toRotationMatrix() * object.linear();
  return turned;
}

// The six directions of the palm frame a grasp is asked to hold a load along.
const Eigen::Vector3d kLoadDirections[] = {Eigen::Vector3d::UnitX(),  -Eigen::Vector3d::UnitX(),
                                           Eigen::Vector3d::UnitY(),  -Eigen::Vector3d::UnitY(),
                                           Eigen::Vector3d::UnitZ(),  -Eigen::Vector3d::UnitZ()};

}  // namespace

std::vector<SupportContact> GripContacts(const ControllerView& view, int lifted) {
  std::vector<SupportContact> contacts;
  for (int k = 0; k < static_cast<int>(view.fingers.size()); ++k) {
    const FingerView& v = view.fingers[k];
    const Eigen::Vector3d inward = v.contact - v.tip;  // the tip sphere's normal into the object
    if (k == lifted || !v.SensesPoint()) continue;
    contacts.push_back({v.contact, inward.normalized()});
  }
  return contacts;
}

double SupportWithout(const ControllerView& view, int lifted, const SupportLimits& limits) {
  return SupportAlong(GripContacts(view, lifted), view.gravity.normalized(),
                      view.object.translation(), limits);
}

ContactChooser::ContactChooser(const HandModel& model, ContactChoiceParams params,
                               SupportParams support)
    : params_(params),
      support_(support),
      kin_(std::make_unique<HandKinematics>(model)) {
  for (int f = 0; f < kin_->num_fingers(); ++f) links_.emplace_back(model, kin_->finger(f));
}

std::vector<ContactCandidate> ContactChooser::Candidates(const ContactRequest& request,
                                                         const ControllerView& view,
                                                         const SurfaceModel& surface) const {
  const Eigen::Vector3d centre = view.object.translation();
  const Eigen::Matrix3d to_palm = view.object.linear();
  const Eigen::Vector3d from_centre = request.point - centre;
  const double reach = from_centre.norm();
  std::vector<ContactCandidate> out;
  if (reach < 1e-6) return out;
  const Eigen::Vector3d d0 = from_centre / reach;
  const Eigen::Vector3d u = d0.unitOrthogonal(), v = d0.cross(u);
  auto add = [&](const Eigen::Vector3d& d, double offset) {
    ContactCandidate c;
    c.offset_rad = offset;
    const SurfacePoint s = surface.Along(to_palm.transpose() * d);
    c.felt = s.known;
    if (offset == 0.0) {
      // The gait's own point, as it chose it.
      c.tip = request.point;
      c.outward = s.known ? Eigen::Vector3d(to_palm * s.normal) : d;
    } else if (s.known) {
      c.outward = to_palm * s.normal;
      c.tip = centre + to_palm * s.point + request.tip_radius_m * c.outward;
    } else {
      c.outward = d;
      c.tip = centre + reach * d;
    }
    c.contact = c.tip - request.tip_radius_m * c.outward;
    out.push_back(c);
  };
  add(d0, 0.0);
  for (int k = 1; k <= params_.rings; ++k) {
    const double offset = params_.spread_rad * k / params_.rings;
    for (int j = 0; j < params_.per_ring; ++j) {
      const double azimuth = 2.0 * M_PI * (j + 0.5 * (k - 1)) / params_.per_ring;
      const Eigen::Vector3d across = std::cos(azimuth) * u + std::sin(azimuth) * v;
      add(std::cos(offset) * d0 + std::sin(offset) * across, offset);
    }
  }
  return out;
}

double ContactChooser::LinkClearance(int f, const Eigen::VectorXd& q, const SurfaceModel& surface,
                                     const Eigen::Isometry3d& object) const {
  // A point this much farther from the centre than any contact is clear by at least a tenth of
  // it (SurfaceClearance's most oblique face): only the nearer ones are asked about.
  constexpr double kFarM = 0.02;
  double extent = 0.0;
  for (const SurfaceContact& c : surface.contacts()) extent = std::max(extent, c.point.norm());
  const Eigen::Vector3d centre = object.translation();
  double least = std::numeric_limits<double>::infinity();
  for (LinkSolid& solid : links_[f].Solids(q)) {
    if (solid.tip) continue;
    const auto far = [&](const Eigen::Vector3d& p) {
      return (p - centre).norm() > extent + kFarM + solid.radius;
    };
    solid.points.erase(std::remove_if(solid.points.begin(), solid.points.end(), far),
                       solid.points.end());
    if (solid.points.empty()) continue;
    if (const auto c = SurfaceClearance(solid, surface, object, params_.extend_surface_m)) {
      least = std::min(least, *c);
    }
  }
  return least;
}

void ContactChooser::Assess(int f, const Eigen::VectorXd& seed, const ContactRequest& request,
                            const ControllerView& view, const SurfaceModel& surface,
                            ContactCandidate* c) const {
  const FingerKinematics& finger = kin_->finger(f);
  const IkParams ik = PlanningIk();
  const IkResult there = SolveFingerIk(finger, seed, c->tip, ik);
  // After the turn the object's centre stays and the contact rides with it.
  const Eigen::Vector3d centre = view.object.translation();
  const Eigen::Isometry3d turned = TurnedInPlace(view.object, request.ride);
  const Eigen::Vector3d tip_after = centre + request.ride * (c->tip - centre);
  const IkResult after = SolveFingerIk(finger, there.q, tip_after, ik);
  c->joints = there.q;
  Eigen::Vector3d tip, axis;
  finger.TipFrame(there.q, &tip, &axis);
  c->contact_angle_rad = std::acos(std::clamp(-axis.dot(c->outward), -1.0, 1.0));
  c->reached = there.residual_m <= params_.reach_tolerance_m &&
               after.residual_m <= params_.reach_tolerance_m &&
               LimitMargin(finger, there.q) >= params_.limit_margin_rad;
  c->link_clearance_m = std::min(LinkClearance(f, there.q, surface, view.object),
                                 LinkClearance(f, after.q, surface, turned));
}

double ContactChooser::Support(int f, const ContactCandidate& c,
                               const ControllerView& view) const {
  std::vector<SupportContact> contacts = GripContacts(view, f);
  contacts.push_back({c.contact, -c.outward});
  const SupportLimits limits = support_.Limits(view.observed_friction);
  double weakest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& d : kLoadDirections) {
    weakest = std::min(weakest, SupportAlong(contacts, d, view.object.translation(), limits));
  }
  return weakest;
}

double ContactChooser::ClearStep(const Eigen::Vector3d& axis_in, double step, int skip,
                                 const ControllerView& view, const SurfaceModel& surface,
                                 int* blocking) const {
  if (blocking != nullptr) *blocking = -1;
  const Eigen::Vector3d axis = axis_in.normalized();
  const Eigen::Vector3d centre = view.object.translation();
  const IkParams ik = PlanningIk();
  struct Rider {
    int finger;
    Eigen::VectorXd q;
    double floor;  // the least clearance it may come to
  };
  std::vector<Rider> riders;
  for (int k = 0; k < static_cast<int>(view.fingers.size()); ++k) {
    if (k == skip || !view.fingers[k].in_contact) continue;
    const Eigen::VectorXd q = PostureNow(kin_->finger(k), view.fingers[k]);
    const double now = LinkClearance(k, q, surface, view.object);
    riders.push_back({k, q, std::min(-params_.link_tolerance_m, now)});
  }
  constexpr int kSamples = 4;
  double allowed = 0.0;
  for (int i = 1; i <= kSamples; ++i) {
    const double phi = step * i / kSamples;
    const Eigen::AngleAxisd turn(phi, axis);
    const Eigen::Isometry3d turned = TurnedInPlace(view.object, turn);
    for (Rider& r : riders) {
      const Eigen::Vector3d tip = centre + turn * (view.fingers[r.finger].tip - centre);
      r.q = SolveFingerIk(kin_->finger(r.finger), r.q, tip, ik).q;
      if (LinkClearance(r.finger, r.q, surface, turned) < r.floor) {
        if (blocking != nullptr) *blocking = r.finger;
        return allowed;
      }
    }
    allowed = phi;
  }
  return allowed;
}

double ContactChooser::LinkClearanceNow(int f, const ControllerView& view,
                                        const SurfaceModel& surface) const {
  return LinkClearance(f, PostureNow(kin_->finger(f), view.fingers[f]), surface, view.object);
}

RideMargins ContactChooser::Ride(int f, const Eigen::Vector3d& axis_in, double step,
                                 const ControllerView& view, const SurfaceModel& surface) const {
  const Eigen::Vector3d axis = axis_in.normalized();
  const Eigen::Vector3d centre = view.object.translation();
  const FingerKinematics& finger = kin_->finger(f);
  const IkParams ik = PlanningIk();
  Eigen::VectorXd q = PostureNow(finger, view.fingers[f]);
  RideMargins m;
  constexpr int kSamples = 4;
  for (int i = 1; i <= kSamples; ++i) {
    const Eigen::AngleAxisd turn(step * i / kSamples, axis);
    const Eigen::Isometry3d turned = TurnedInPlace(view.object, turn);
    const IkResult r = SolveFingerIk(finger, q, centre + turn * (view.fingers[f].tip - centre), ik);
    q = r.q;
    m.reached = m.reached && r.residual_m <= params_.reach_tolerance_m;
    m.limit_margin_rad = std::min(m.limit_margin_rad, LimitMargin(finger, q));
    m.link_clearance_m = std::min(m.link_clearance_m, LinkClearance(f, q, surface, turned));
  }
  return m;
}

ContactChoice ContactChooser::Choose(const ContactRequest& request, const ControllerView& view,
                                     const SurfaceModel& surface) const {
  ContactChoice choice;
  choice.candidates = Candidates(request, view, surface);
  if (choice.candidates.empty()) {
    choice.why = "no direction from the centre";
    return choice;
  }
  const int f = request.finger;
  const FingerKinematics& finger = kin_->finger(f);
  const Eigen::VectorXd now = PostureNow(finger, view.fingers[f]);
  for (ContactCandidate& c : choice.candidates) {
    Assess(f, now, request, view, surface, &c);
    for (int k = 0; k < static_cast<int>(view.fingers.size()); ++k) {
      if (k != f && view.fingers[k].in_contact) {
        c.spacing_m = std::min(c.spacing_m, (c.tip - view.fingers[k].tip).norm());
      }
    }
    c.support_n = Support(f, c, view);
  }
  Select(request, &choice);
  return choice;
}

ContactCandidate ContactChooser::AtPoint(const ContactRequest& request,
                                         const ControllerView& view,
                                         const SurfaceModel& surface) const {
  std::vector<ContactCandidate> candidates = Candidates(request, view, surface);
  DMPL_DEMAND(!candidates.empty());  // a point at the object's centre: no direction to it
  ContactCandidate& c = candidates.front();
  Assess(request.finger, PostureNow(kin_->finger(request.finger), view.fingers[request.finger]),
         request, view, surface, &c);
  return c;
}

void ContactChooser::Select(const ContactRequest& request, ContactChoice* out) const {
  ContactChoice& choice = *out;
  auto viable = [&](const ContactCandidate& c) {
    return c.reached && c.spacing_m >= request.min_spacing_m;
  };
  auto clear = [&](const ContactCandidate& c) {
    return c.link_clearance_m >= -params_.link_tolerance_m &&
           (params_.max_contact_angle_rad <= 0 ||
            c.contact_angle_rad <= params_.max_contact_angle_rad);
  };
  const ContactCandidate& gait = choice.candidates[0];
  if (viable(gait) && clear(gait)) {
    choice.why = "the gait's point";
    if (params_.better_support <= 0) return;
    int best = 0;
    for (int i = 1; i < static_cast<int>(choice.candidates.size()); ++i) {
      const ContactCandidate& c = choice.candidates[i];
      if (viable(c) && clear(c) && c.support_n > choice.candidates[best].support_n) best = i;
    }
    if (choice.candidates[best].support_n > params_.better_support * gait.support_n) {
      choice.index = best;
      choice.why = "more support";
    }
    return;
  }
  // The nearest viable and clear one; of a ring, the best supported.
  int best = -1;
  for (int i = 0; i < static_cast<int>(choice.candidates.size()); ++i) {
    const ContactCandidate& c = choice.candidates[i];
    if (!viable(c) || !clear(c)) continue;
    const ContactCandidate* b = best < 0 ? nullptr : &choice.candidates[best];
    if (b == nullptr || c.offset_rad < b->offset_rad - 1e-9 ||
        (c.offset_rad < b->offset_rad + 1e-9 && c.support_n > b->support_n)) {
      best = i;
    }
  }
  if (best >= 0) {
    choice.index = best;
    choice.why = viable(gait) ? "links clear" : "within reach and apart";
    return;
  }
  // Nothing clear: the viable one whose links come least close.
  for (int i = 0; i < static_cast<int>(choice.candidates.size()); ++i) {
    const ContactCandidate& c = choice.candidates[i];
    if (!viable(c)) continue;
    if (best < 0 || c.link_clearance_m > choice.candidates[best].link_clearance_m) best = i;
  }
  if (best > 0 &&
      choice.candidates[best].link_clearance_m > gait.link_clearance_m + params_.link_tolerance_m) {
    choice.index = best;
    choice.why = "links least close";
  } else {
    choice.why = best < 0 ? "nothing within reach and apart: the gait's point"
                          : "nothing clearer: the gait's point";
  }
}

}  // namespace dmpl
