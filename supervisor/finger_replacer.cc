#include "supervisor/finger_replacer.h"

#include <algorithm>

namespace dmpl {

FingerReplacer::FingerReplacer(Blackboard* board, const SupervisorParams& params)
    : board_(board),
      params_(params),
      stage_(board->fingers.size(), Stage::kNone),
      since_(board->fingers.size(), 0.0) {}

void FingerReplacer::Reset() { std::fill(stage_.begin(), stage_.end(), Stage::kNone); }

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
        if (board_->reached[f] || since > 1.5) BringIn(f);
        break;
      case Stage::kIn:
        // Touching: done; still nothing after a while: lift and try again.
        if (touching || since > 1.0) stage_[f] = Stage::kNone;
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

bool FingerReplacer::RestsOnLink(int f) const {
  const FingerView& v = board_->view.fingers[f];
  return params_.replace_on_link && board_->on_link[f] &&
         board_->out.task.fingers[f].role == Role::kGrip &&
         board_->now - board_->on_link_since[f] > params_.link_rest_s &&
         v.force < params_.link_rest_tip_share * v.desired_force;
}

void FingerReplacer::Lift(int f, const std::string& why) {
  // Off the surface along the line from the centre.
  const Eigen::Vector3d& tip = board_->view.fingers[f].tip;
  Eigen::Vector3d out = tip - board_->view.object.translation();
  if (out.norm() < 1e-6) out = board_->home[f] - board_->home_centre;
  const Eigen::Vector3d target = tip + params_.replace_lift_m * out.normalized();
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
  const Eigen::Vector3d home = board_->home[f] - board_->home_centre;
  const Eigen::Vector3d target = board_->view.object.translation() +
                                 home.normalized() * (home.norm() + params_.replace_lift_m);
  board_->SetFinger(f, Role::kFree, Primitive::kPosition, &target);
  board_->reached[f] = false;
  stage_[f] = Stage::kOver;
  since_[f] = board_->now;
  board_->out.changed = true;
}

void FingerReplacer::BringIn(int f) {
  board_->SetFinger(f, Role::kGrip, Primitive::kComposite);
  stage_[f] = Stage::kIn;
  since_[f] = board_->now;
  board_->out.changed = true;
}

}  // namespace dmpl
