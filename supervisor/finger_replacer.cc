#include "supervisor/finger_replacer.h"

#include <algorithm>

namespace dmpl {

FingerReplacer::FingerReplacer(Blackboard* board, const SupervisorParams& params,
                               const ContactChooser* chooser, double min_spacing_m)
    : board_(board),
      params_(params),
      chooser_(chooser),
      min_spacing_m_(min_spacing_m),
      stage_(board->fingers.size(), Stage::kNone),
      since_(board->fingers.size(), 0.0),
      shift_(board->fingers.size(), 0.0),
      base_side_(board->fingers.size(), Eigen::Vector3d::Zero()),
      stall_at_(board->fingers.size(), Eigen::Vector3d::Zero()),
      stalled_since_(board->fingers.size(), 0.0) {}

void FingerReplacer::Reset() {
  std::fill(stage_.begin(), stage_.end(), Stage::kNone);
  std::fill(shift_.begin(), shift_.end(), 0.0);
}

bool FingerReplacer::placing() const {
  return std::any_of(stage_.begin(), stage_.end(), [](Stage s) { return s != Stage::kNone; });
}

void FingerReplacer::Tick(double recovery_since) {
  if (params_.replace_after_s <= 0) return;
  const double now = board_->now;
  for (int f = 0; f < board_->num_fingers(); ++f) {
    const double since = now - since_[f];
    const bool touching = board_->view.fingers[f].in_contact;
    switch (stage_[f]) {
      case Stage::kNone:
        // At once (the recovery may have begun for it, LinkRest), while the others all touch.
        if (RestsOnLink(f) && OthersTouch(f)) {
          Lift(f, ": its links touch");
        } else if (!touching && now - recovery_since > params_.replace_after_s) {
          Lift(f, "");
        }
        break;
      case Stage::kLift:
        if (board_->reached[f] || since > 1.0) MoveOverHome(f);
        break;
      case Stage::kOver:
        // A tip that meets the surface on its way over grips there: pressing on toward a point
        // inside the object would push the object or lay a link on it.
        if (touching || board_->reached[f] || since > 1.5) BringIn(f);
        break;
      case Stage::kIn:
        // Touching: done; stopped short of the surface (its links on the object, or another
        // finger in the way): lift and try a point nearer its base; still nothing after a
        // while: lift and try again.
        if (touching) {
          stage_[f] = Stage::kNone;
        } else if (Stalled(f)) {
          base_side_[f] = -board_->view.fingers[f].tip_axis;
          shift_[f] = std::min(shift_[f] + params_.replace_shift_rad, params_.replace_max_shift_rad);
          Lift(f, ": it stopped short of the surface");
        } else if (since > 1.0) {
          stage_[f] = Stage::kNone;
        }
        break;
    }
  }
}

bool FingerReplacer::OthersTouch(int f) const {
  for (int k = 0; k < board_->num_fingers(); ++k) {
    if (k != f && (stage_[k] != Stage::kNone || !board_->view.fingers[k].in_contact)) return false;
  }
  return true;
}

bool FingerReplacer::Stalled(int f) {
  const FingerView& v = board_->view.fingers[f];
  if (params_.replace_shift_rad <= 0 || v.in_contact) return false;
  // Moving in: not stalled yet (the clock starts again wherever it has got to).
  if ((v.tip - stall_at_[f]).norm() > params_.replace_stall_m) {
    stall_at_[f] = v.tip;
    stalled_since_[f] = board_->now;
  }
  return board_->now - stalled_since_[f] >= params_.replace_stall_s;
}

bool FingerReplacer::RestsOnLink(int f) const {
  const FingerView& v = board_->view.fingers[f];
  return params_.replace_on_link && board_->on_link[f] &&
         board_->out.task.fingers[f].role == Role::kGrip &&
         board_->now - board_->on_link_since[f] > params_.link_rest_s &&
         v.force < params_.link_rest_tip_share * v.desired_force;
}

void FingerReplacer::Lift(int f, const std::string& why) {
  // Off the surface along the line from the centre.
  const Eigen::Vector3d target = board_->LiftedOff(f, params_.replace_lift_m);
  board_->SetFinger(f, Role::kFree, Primitive::kPosition, &target);
  board_->reached[f] = false;
  // Lifted, its links touch nothing: a LINK_RELEASED lost on the way (real time) leaves no
  // stale touch behind to begin another recovery.
  board_->on_link[f] = false;
  stage_[f] = Stage::kLift;
  since_[f] = board_->now;
  board_->Note("placing finger " + board_->fingers[f] + " again" + why);
}

void FingerReplacer::MoveOverHome(int f) {
  const Eigen::Vector3d direction = PlacementDirection(f);
  // As far out as its home, or as the felt surface there where the model knows it lies farther
  // (a point inside it would be pushed into the object by a position move).
  double out = (board_->home[f] - board_->home_centre).norm();
  const Eigen::Matrix3d to_palm = board_->view.object.linear();
  const SurfacePoint felt = board_->surface.Along(to_palm.transpose() * direction);
  if (felt.Differs(out - board_->tip_radius_m)) {
    out = std::max(out, felt.distance_m + board_->tip_radius_m);
  }
  // Summed as before, to the last bit: without the option a recovery is the one of before.
  const Eigen::Vector3d centre = board_->view.object.translation();
  Eigen::Vector3d target = centre + direction * (out + params_.replace_lift_m);
  Eigen::Vector3d tip, away;
  if (ChooseOnFeltSurface(f, centre + direction * out, &tip, &away)) {
    target = tip + away * params_.replace_lift_m;
  }
  board_->SetFinger(f, Role::kFree, Primitive::kPosition, &target);
  board_->reached[f] = false;
  stage_[f] = Stage::kOver;
  since_[f] = board_->now;
  board_->out.changed = true;
}

Eigen::Vector3d FingerReplacer::PlacementDirection(int f) const {
  const Eigen::Vector3d d = (board_->home[f] - board_->home_centre).normalized();
  // Toward the base: against the tip's axis as it stalled, across the direction.
  const Eigen::Vector3d back = base_side_[f] - base_side_[f].dot(d) * d;
  if (shift_[f] <= 0 || back.norm() < 1e-6) return d;
  return Eigen::AngleAxisd(shift_[f], d.cross(back).normalized()) * d;
}

bool FingerReplacer::ChooseOnFeltSurface(int f, const Eigen::Vector3d& planned,
                                         Eigen::Vector3d* tip, Eigen::Vector3d* away) {
  if (chooser_ == nullptr || !params_.replace_on_felt_surface || board_->tip_radius_m <= 0) {
    return false;
  }
  ContactRequest request;  // no ride: it grips where it lands, and the object is held still
  request.finger = f;
  request.point = planned;
  request.tip_radius_m = board_->tip_radius_m;
  request.min_spacing_m = min_spacing_m_;
  const ContactChoice choice = chooser_->Choose(request, board_->view, board_->surface);
  if (choice.index == 0) return false;
  const ContactCandidate& c = choice.chosen();
  *tip = c.tip;
  *away = c.outward;
  board_->Note("placing finger " + board_->fingers[f] + " again at " + Fixed(c.offset_rad) +
               " rad from its point (" + choice.why + ": links " +
               Fixed(1e3 * c.link_clearance_m, 1) + " mm off; there " +
               Fixed(1e3 * choice.candidates[0].link_clearance_m, 1) + " mm)");
  return true;
}

void FingerReplacer::BringIn(int f) {
  board_->SetFinger(f, Role::kGrip, Primitive::kComposite);
  stall_at_[f] = board_->view.fingers[f].tip;
  stalled_since_[f] = board_->now;
  stage_[f] = Stage::kIn;
  since_[f] = board_->now;
  board_->out.changed = true;
}

}  // namespace dmpl
