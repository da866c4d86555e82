#include "supervisor/gait.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

#include "supervisor/edge_hop.h"
#include "supervisor/explorer_choice.h"

namespace dmpl {

Gait::Gait(Blackboard* board, ObjectGoal* goal, const GaitSpec& spec, const TaskParams& params,
           uint64_t seed, Report report, const ContactChooser* chooser)
    : board_(board),
      goal_(goal),
      spec_(spec),
      params_(params),
      seed_(seed),
      report_(std::move(report)),
      chooser_(chooser),
      geometry_(board->home, board->home_centre, spec, params.max_finger_deviation_rad),
      link_block_(board->fingers.size(), LinkBlock::kNone),
      regrasp_(this, board->fingers, spec.order, params.turn.mode, params.grip_while_turning) {}

void Gait::Start() {
  board_->AllGrip();
  geometry_ = GaitGeometry(board_->home, board_->home_centre, spec_,
                           params_.max_finger_deviation_rad);
  goal_->CommandInAll(params_.angle);
  if (params_.has_goals()) StartGoals();
  done_ = false;
  explorer_ = -1;
  struck_.assign(board_->num_fingers(), false);
  lifted_ = placed_back_ = -1;
  deferred_turn_ = nullptr;
  phase_since_ = board_->now;
  regrasp_.Process(RegraspEvent::Begin);
}

void Gait::Resume() {
  phase_since_ = board_->now;
  regrasp_.Process(RegraspEvent::Begin);
}

void Gait::Abort() {
  regrasp_.Process(RegraspEvent::Abort);
  explorer_ = -1;
  explore_.hop = Hop::kNone;
  lifted_ = placed_back_ = -1;  // the recovery grips with all
  deferred_turn_ = nullptr;
}

void Gait::StartGoals() {
  std::vector<Eigen::Quaterniond> goals;
  for (const OrientationParam& g : params_.goals) goals.push_back(g.q);
  const Eigen::Quaterniond from = goals.empty() ? board_->SensedOrientation() : goals.back();
  for (const auto& q : RandomGoals(seed_, params_.random_goals,
                                   params_.random_goal_separation_rad, from)) {
    goals.push_back(q);
  }
  goals_ = GoalSequence(std::move(goals), params_.goal_tolerance_rad, params_.goal_hold_s,
                        params_.goal_timeout_s);
  goals_.Start(board_->now);
}

double Gait::StepSpeed() const {
  const double overlap = params_.overlap_angular_speed;
  return regrasp_.exploring() && regrasp_.overlapping() && overlap > 0 ? overlap
                                                                       : params_.angular_speed;
}

void Gait::Explore(const std::string& finger) {
  const int f = board_->Finger(finger);
  pending_choice_.pending = false;
  explorer_ = f;
  // A finger that sits the turns out comes back to hold while the next one explores: the
  // step after its grip holds the object still.
  if (f == lifted_) lifted_ = -1;
  if (params_.struck_fingers.enabled && struck_[f]) placed_back_ = f;
  phase_since_ = board_->now;
  board_->reached[f] = false;
  // Toward a goal orientation the steps turn about the axis to it (positive angles).
  const double sign = params_.has_goals() || params_.angle >= 0 ? 1.0 : -1.0;
  const Eigen::Vector3d axis = StepAxis();
  // With four the explorer rides every step; when the others turn while it slides, all but one.
  const bool four = regrasp_.turn() == RegraspChart::Turn::kFourFingers ||
                    (regrasp_.turn() == RegraspChart::Turn::kAuto && !regrasp_.overlapping());
  const bool spaced = spec_.tip_clearance_m > 0 && geometry_.AroundFingers(axis);
  step_limit_ = spaced ? geometry_.StepLimit(axis, board_->view, params_.step / 4.0) : 0.0;
  const Eigen::AngleAxisd turn(ExploreBack(f, axis, sign, four), axis);
  explore_.point =
      geometry_.ExplorePoint(f, turn, board_->view, board_->surface, board_->tip_radius_m,
                             params_.explore_max_elevation_rad, params_.explore_face_partner_rad);
  if (params_.max_contact_angle_rad > 0) {
    explore_.point = geometry_.TowardTipFront(f, explore_.point, board_->view, board_->surface,
                                              board_->tip_radius_m, params_.max_contact_angle_rad);
  }
  std::string chosen;
  // Where it lands: the others turn the object while it slides, unless it rides every step.
  const Eigen::Matrix3d landing =
      (four ? Eigen::Matrix3d::Identity()
            : Eigen::AngleAxisd(sign * StepSize(), axis).toRotationMatrix()) *
      board_->view.object.linear();
  explore_.point = KeepOnFace(explore_.point, landing, &chosen);
  explore_.point = ChooseContact(f, explore_.point, axis, sign,
                                 four ? board_->num_fingers() : board_->num_fingers() - 1,
                                 &chosen);
  board_->link_touched[f] = false;
  if (link_block_[f] == LinkBlock::kBlocked) link_block_[f] = LinkBlock::kPlaced;
  explore_.axis = axis;
  explore_.spaced = spaced;
  explore_.neighbour_rides = !four;
  explore_.sign = sign;
  explore_.target = spaced ? geometry_.KeepClear(f, axis, sign, StepSize(), !four, explore_.point,
                                                 board_->view)
                           : explore_.point;
  board_->NewTask(regrasp_.last_action());
  board_->AllGrip();
  explore_.hop_since = board_->now;
  explore_.on_link_since = -1.0;
  explore_.link_lifts = 0;
  explore_.object = board_->view.object;
  if (HopsOverEdge(f)) {
    // First eased to the explorer's force where it stands, so that the others take the load
    // as they would from any explorer, before it lifts.
    explore_.hop = Hop::kEase;
    const Eigen::Vector3d here = board_->view.fingers[f].tip;
    board_->SetFinger(f, Role::kExplore, Primitive::kHybrid, &here, params_.explore_force_n);
    chosen += std::string(chosen.empty() ? "" : ", ") + "stepping over an edge on its way";
  } else {
    explore_.hop = Hop::kNone;
    board_->SetFinger(f, Role::kExplore, Primitive::kHybrid, &explore_.target,
                      params_.explore_force_n);
  }
  goal_->Send();
  if (!board_->view.gravity.isZero()) {
    std::ostringstream note;
    note << std::fixed << std::setprecision(2) << finger << " explores; the others hold "
         << SupportWithout(board_->view, f, SupportLimitsNow()) << " N against gravity";
    if (params_.support.observed && board_->view.observed_friction > 0.0) {
      note << " (friction " << SupportLimitsNow().friction << ", "
           << board_->view.observed_friction << " observed)";
    }
    if (params_.explorer_support.need_weights > 0.0 && board_->view.observed_weight_n > 0.0) {
      note << "; it weighs " << board_->view.observed_weight_n << " N as the tips feel it";
    }
    if (!chosen.empty()) note << "; " << chosen;
    board_->Note(note.str());
  } else if (!chosen.empty()) {
    board_->Note(finger + " explores " + chosen);
  }
}

Eigen::Vector3d Gait::ChooseContact(int f, const Eigen::Vector3d& point,
                                    const Eigen::Vector3d& axis, double sign, double rides,
                                    std::string* why) {
  if (chooser_ == nullptr || !params_.contact_choice.enabled || board_->tip_radius_m <= 0) {
    return point;
  }
  ContactRequest request;
  request.finger = f;
  request.point = point;
  request.ride = Eigen::AngleAxisd(sign * rides * StepSize(), axis.normalized());
  request.tip_radius_m = board_->tip_radius_m;
  request.min_spacing_m = spec_.tip_clearance_m;
  const ContactChoice choice = chooser_->Choose(request, board_->view, board_->surface);
  if (choice.index == 0) return point;
  const ContactCandidate& c = choice.chosen();
  auto degrees = [](double rad) { return Fixed(rad * 180.0 / M_PI, 0); };
  const ContactCandidate& own = choice.candidates[0];
  *why += std::string(why->empty() ? "" : ", ") + "at " + Fixed(c.offset_rad) +
          " rad from the gait's point (" + choice.why + ": links " +
          Fixed(1e3 * c.link_clearance_m, 1) + " mm off, " + degrees(c.contact_angle_rad) +
          " deg round the tip, support " + Fixed(c.support_n) + " N; there " +
          Fixed(1e3 * own.link_clearance_m, 1) + " mm, " + degrees(own.contact_angle_rad) +
          " deg, " + Fixed(own.support_n) + " N)";
  return c.tip;
}

Eigen::Vector3d Gait::KeepOnFace(const Eigen::Vector3d& point, const Eigen::Matrix3d& landing,
                                 std::string* why) const {
  if (params_.face_bounds.margin_m <= 0) return point;
  const Eigen::Vector3d centre = board_->view.object.translation();
  double moved = 0.0;
  const Eigen::Vector3d kept = KeepInsideFace(landing.transpose() * (point - centre),
                                              board_->surface, board_->flat_faces,
                                              params_.face_bounds, &moved);
  if (moved <= 0.0) return point;
  *why += std::string(why->empty() ? "" : ", ") + "kept " + Fixed(1e3 * moved, 1) +
          " mm further inside its face";
  return centre + landing * kept;
}

double Gait::StepClearOfLinks(const Eigen::Vector3d& axis, double step) {
  const ContactChoiceParams& c = params_.contact_choice;
  if (chooser_ == nullptr || !c.enabled || !c.clear_steps) return step;
  int blocking = -1;
  const int skip = regrasp_.exploring() ? explorer_ : -1;
  const double clear =
      chooser_->ClearStep(axis, step, skip, board_->view, board_->surface, &blocking);
  const bool replaced = blocking >= 0 && link_block_[blocking] == LinkBlock::kPlaced;
  // A finger placed again after it stopped a step counts for this step only.
  for (LinkBlock& b : link_block_) {
    if (b == LinkBlock::kPlaced) b = LinkBlock::kNone;
  }
  // Placed again where the chooser found it best, it stops the step no more: else the gait would
  // stall on a turn no placement clears.
  if (blocking < 0 || replaced) return step;
  link_block_[blocking] = LinkBlock::kBlocked;
  // Placed again on its tip, where the chooser finds its links clear.
  regrasp_.set_next_explorer(board_->fingers[blocking]);
  board_->Note("the step stops at " + Fixed(clear) + " of " + Fixed(step) + " rad: " +
               board_->fingers[blocking] +
               "'s links would enter the felt surface; it explores next");
  return clear;
}

double Gait::ExploreBack(int f, const Eigen::Vector3d& axis, double sign, bool four) const {
  // Back against the rotation, so that the finger never drifts to its joint limits.
  const double n = static_cast<double>(board_->num_fingers());
  const double rides = four ? n : n - 1;
  const double back = -sign * params_.explore_travel * rides * StepSize() / 2.0;
  // No further back than the deviation allows.
  return LimitDeviation() ? geometry_.LimitBack(f, axis, back) : back;
}

void Gait::Rotate(const std::vector<std::string>& /*grippers*/) {
  // The explorer, if any, keeps exploring in place; the others grip.
  phase_since_ = board_->now;
  board_->NewTask(regrasp_.last_action());
  if (!params_.has_goals()) {
    const double remaining = goal_->remaining();
    step_ = std::copysign(std::min(StepSize(), std::abs(remaining)), remaining);
    step_ = StepClearOfLinks(params_.axis.direction, step_);
    HoldStillForPlacedBack();
    const Eigen::Vector3d axis = params_.axis.direction;
    TurnOrSitOut([this, axis, step = step_] { goal_->Turn(axis, step, StepSpeed()); });
    return;
  }
  // One step from where the object is toward the current goal, the shortest way.
  const AxisAngle to_goal = RotationToGoal(board_->SensedOrientation(), goals_.current());
  step_ = std::min(StepSize(), to_goal.angle);
  if (LimitDeviation()) {
    // The explorer, if it slides meanwhile, does not ride this step.
    const int skip = regrasp_.exploring() ? explorer_ : -1;
    step_ = geometry_.StepWithinReach(to_goal.axis, step_, skip, board_->view);
    ChooseNextExplorer(to_goal.axis, step_ + StepSize(), skip);
  }
  step_ = StepClearOfLinks(to_goal.axis, step_);
  PreferFingerAtRisk(regrasp_.exploring() ? explorer_ : -1);
  HoldStillForPlacedBack();
  const Eigen::Matrix3d pose =
      (Eigen::AngleAxisd(step_, to_goal.axis) * board_->SensedOrientation()).toRotationMatrix();
  TurnOrSitOut([this, pose, step = step_] { goal_->Aim(pose, step, StepSpeed()); });
}

void Gait::TurnOrSitOut(std::function<void()> turn) {
  const int struck = StruckFingerToLift(regrasp_.exploring() ? explorer_ : -1);
  if (struck >= 0 && regrasp_.gripping_while_turning()) {
    // The finger that grips now must hold before another lets go: the turn waits for its grip.
    deferred_turn_ = [this, struck, turn = std::move(turn)] {
      LiftOff(struck);
      turn();
    };
    return;
  }
  if (struck >= 0) LiftOff(struck);
  turn();
}

void Gait::HoldStillForPlacedBack() {
  if (placed_back_ < 0) return;
  placed_back_ = -1;
  step_ = 0.0;
}

bool Gait::StartDeferredTurn(double in_phase) {
  if (!deferred_turn_) return false;
  if (!GripDue(in_phase)) return true;
  const std::function<void()> turn = std::move(deferred_turn_);
  deferred_turn_ = nullptr;
  turn();
  phase_since_ = board_->now;
  return true;
}

bool Gait::GripDue(double in_phase) const {
  return (board_->view.grasp_stable && in_phase > 0.05) || in_phase > spec_.grip_timeout_s;
}

void Gait::NoteStruckFingers() {
  if (!params_.struck_fingers.enabled || step_ == 0.0) return;
  for (int f = 0; f < board_->num_fingers(); ++f) {
    if (struck_[f] || !board_->on_link[f] || board_->out.task.fingers[f].role != Role::kGrip) {
      continue;
    }
    struck_[f] = true;
    board_->Note(board_->fingers[f] + "'s links met the object in a turn: it sits the turns out");
  }
}

double Gait::SupportNeeded() const {
  const ExplorerSupportParams& e = params_.explorer_support;
  const double weight = board_->view.observed_weight_n;
  return e.need_weights > 0.0 && weight > 0.0 ? e.need_weights * weight : e.need_n;
}

SupportLimits Gait::SupportLimitsNow() const {
  return params_.support.Limits(board_->view.observed_friction);
}

int Gait::StruckFingerToLift(int skip) const {
  const StruckFingerParams& p = params_.struck_fingers;
  if (!p.enabled || lifted_ >= 0 || step_ == 0.0) return -1;
  const ControllerView& view = board_->view;
  for (int f = 0; f < board_->num_fingers(); ++f) {
    if (!struck_[f] || f == skip || !view.fingers[f].in_contact) continue;
    if (view.gravity.isZero() || SupportWithout(view, f, SupportLimitsNow()) >= p.need_n) {
      return f;
    }
  }
  return -1;
}

void Gait::LiftOff(int f) {
  const ControllerView& view = board_->view;
  const Eigen::Vector3d off = board_->LiftedOff(f, params_.struck_fingers.lift_m);
  board_->SetFinger(f, Role::kFree, Primitive::kPosition, &off);
  board_->out.changed = true;
  lifted_ = f;
  board_->Note(board_->fingers[f] + " sits this turn out; the others hold " +
               Fixed(SupportWithout(view, f, SupportLimitsNow())) + " N against gravity");
}

void Gait::Grip(const std::string& finger) {
  phase_since_ = board_->now;
  explorer_ = -1;
  board_->NewTask(regrasp_.last_action());
  board_->SetFinger(board_->Finger(finger), Role::kGrip, Primitive::kComposite);
  if (LimitDeviation()) ChooseNextExplorer(StepAxis(), StepSize(), -1);
  PreferFingerAtRisk(-1);
}

void Gait::PreferFingerAtRisk(int skip) {
  if (params_.max_contact_angle_rad <= 0) return;
  int worst = -1;
  double most = 0.0;
  for (int k = 0; k < board_->num_fingers(); ++k) {
    const FingerView& v = board_->view.fingers[k];
    if (k == skip || !v.in_contact) continue;
    // A link's touch outweighs any angle; beyond the angle, the further the worse.
    const double risk = (board_->link_touched[k] ? M_PI : 0.0) +
                        std::max(0.0, v.ContactAngle() - params_.max_contact_angle_rad);
    if (risk > most) {
      most = risk;
      worst = k;
    }
  }
  if (worst >= 0) regrasp_.set_next_explorer(board_->fingers[worst]);
}

void Gait::ChooseNextExplorer(const Eigen::Vector3d& axis, double step, int skip) {
  const ExplorerSupportParams& e = params_.explorer_support;
  const WaitRule rule{e.slack_rad, SupportNeeded(), e.palm_side_rad, e.wait_max_contact_angle_rad};
  const ExplorerChoice next =
      NextExplorer(geometry_, axis, step, skip, board_->view, SupportLimitsNow(), rule);
  pending_choice_ = {next.grasp_unknown, axis, step, skip};
  if (next.finger < 0) return;
  int finger = next.finger;
  std::string why;
  if (finger != next.furthest && !FurthestMayRide(axis, step, next.furthest, &why)) {
    finger = next.furthest;
  }
  if (board_->fingers[finger] != regrasp_.next_explorer()) {
    if (finger != next.furthest) {
      board_->Note(board_->fingers[finger] + " explores next, not " +
                   board_->fingers[next.furthest] + ": the others hold " + Fixed(next.support_n) +
                   " N against gravity without it, " + Fixed(next.furthest_support_n) + " N");
    } else if (!why.empty()) {
      board_->Note(board_->fingers[finger] + " explores next, not " +
                   board_->fingers[next.finger] + ": " + why);
    }
  }
  regrasp_.set_next_explorer(board_->fingers[finger]);
}

bool Gait::FurthestMayRide(const Eigen::Vector3d& axis, double step, int f,
                           std::string* why) const {
  const ExplorerSupportParams& e = params_.explorer_support;
  if (!e.check_ride || chooser_ == nullptr) return true;
  const RideMargins m = chooser_->Ride(f, axis, step, board_->view, board_->surface);
  if (!m.reached) {
    *why = "riding the step its tip would not follow the object";
  } else if (m.link_clearance_m < e.ride_clearance_m) {
    *why = "riding the step its links would come " + Fixed(1e3 * m.link_clearance_m, 1) +
           " mm off the felt surface";
  } else if (m.limit_margin_rad < e.ride_limit_margin_rad) {
    *why = "riding the step its joints would come " + Fixed(m.limit_margin_rad) +
           " rad from their limits";
  }
  return why->empty();
}

Eigen::Vector3d Gait::StepAxis() const {
  return params_.has_goals()
             ? RotationToGoal(board_->SensedOrientation(), goals_.current()).axis
             : params_.axis.direction;
}

double Gait::StepSize() const {
  return step_limit_ > 0 ? std::min(params_.step, step_limit_) : params_.step;
}

void Gait::KeepExplorerClear() {
  if (!explore_.spaced || explorer_ < 0) return;
  // About the axis the explore began with: a goal reached meanwhile turns the next steps about
  // another one, and the explorer's point was chosen for this one.
  const Eigen::Vector3d axis = explore_.axis.normalized();
  // What the step still has to turn about the axis: the finger it slides toward rides it.
  double remaining = 0.0;
  if (explore_.neighbour_rides && goal_->has_goal()) {
    const Eigen::AngleAxisd left(goal_->pose().linear() * board_->view.object.linear().transpose());
    remaining = std::clamp(std::abs(left.angle() * left.axis().dot(axis)), 0.0, std::abs(step_));
  }
  const Eigen::Vector3d target =
      geometry_.KeepClear(explorer_, axis, explore_.sign, remaining, explore_.neighbour_rides,
                          explore_.point, board_->view);
  if ((target - explore_.target).norm() < 1e-3) return;  // not for the estimate's noise
  explore_.target = target;
  board_->out.task.fingers[explorer_].target = target;
  board_->reached[explorer_] = false;
  board_->out.changed = true;
}

bool Gait::CanTurnWithout(const std::string& /*finger*/) const {
  // The fingers stand around one axis of the palm (gait.overlap_about): about it, any three of
  // them turn the object while the fourth slides back; about an axis tilted from it they push
  // the object along that axis too, which needs the fourth's support (measured: three alone
  // lose the object about y, z and the diagonal; four turn it).
  return geometry_.AroundFingers(StepAxis());
}

bool Gait::GoalReached() const {
  if (params_.has_goals()) return goals_.complete();
  return std::abs(goal_->remaining()) < 1e-9;
}

bool Gait::StepDone(double in_phase) const {
  // The reference needs |step| / speed to arrive; after that and a moment to settle, an object
  // close enough to its goal has done its step.
  const double travel = std::abs(step_) / StepSpeed();
  const bool settled = in_phase > travel + spec_.settle_time_s &&
                       board_->view.tracking_error_rad < spec_.settle_tolerance_rad;
  return board_->MotionDone() || settled;
}

bool Gait::TickGoals() {
  switch (goals_.Update(board_->now, board_->SensedOrientation())) {
    case GoalSequence::Event::kReached:
      board_->Note("goal " + std::to_string(goals_.reached()) + " of " +
                   std::to_string(goals_.size()) + " reached in " +
                   Fixed(goals_.times_s().back()) + " s");
      report_(GaitReport::kGoalReached, "");
      if (goals_.complete()) done_ = true;
      // The next goal turns about another axis: which links meet the object is learned anew.
      std::fill(struck_.begin(), struck_.end(), false);
      return true;
    case GoalSequence::Event::kTimedOut:
      report_(GaitReport::kFailed,
              "goal " + std::to_string(goals_.reached() + 1) + " not reached within " +
                  Fixed(params_.goal_timeout_s, 1) + " s (" + Fixed(goals_.error_rad()) +
                  " rad from it)");
      return false;
    case GoalSequence::Event::kNone:
      return true;
  }
  return true;
}

void Gait::Tick() {
  const double in_phase = board_->now - phase_since_;
  if (params_.has_goals() && !TickGoals()) return;
  if (pending_choice_.pending) {
    ChooseNextExplorer(pending_choice_.axis, pending_choice_.step, pending_choice_.skip);
  }
  if (regrasp_.exploring()) {
    TickExplore(in_phase);
  } else if (regrasp_.rotating()) {
    TickRotate(in_phase);
  } else {
    TickGrip(in_phase);
  }
  if (done_) report_(GaitReport::kDone, "");
}

void Gait::TickExplore(double in_phase) {
  const bool hopping = LiftOffLink() || TickHop();
  if (!hopping) KeepExplorerClear();
  const bool there = !hopping && explorer_ >= 0 && board_->reached[explorer_] &&
                     board_->view.fingers[explorer_].in_contact;
  // Continuous: the three turn the object while the explorer slides; both must be done.
  const bool turned = !regrasp_.overlapping() || StepDone(in_phase);
  if ((there && turned) || in_phase > spec_.explore_timeout_s) {
    if (!there) {
      board_->Note("explorer " + board_->fingers[explorer_] + " did not reach its point in time");
    }
    if (!turned) board_->Note("the step did not finish while the explorer slid");
    explore_.hop = Hop::kNone;  // in time or not, it grips from where it is
    regrasp_.Process(RegraspEvent::ExploreReady);
  }
}

bool Gait::LiftOffLink() {
  const ExplorerLinkParams& p = params_.explorer_link;
  const int f = explorer_;
  const bool on_link = p.enabled && f >= 0 && explore_.hop == Hop::kNone && board_->on_link[f] &&
                       !board_->view.fingers[f].in_contact;
  if (!on_link) {
    explore_.on_link_since = -1.0;
    return false;
  }
  if (explore_.on_link_since < 0) explore_.on_link_since = board_->now;
  if (board_->now - explore_.on_link_since < p.after_s || explore_.link_lifts >= p.tries) {
    return false;
  }
  ++explore_.link_lifts;
  explore_.on_link_since = -1.0;
  LiftExplorer();
  board_->Note(board_->fingers[f] + " explores on a link: lifted off to come at its point again");
  return true;
}

void Gait::LiftExplorer() {
  const int f = explorer_;
  const Eigen::Vector3d lifted = board_->LiftedOff(f, params_.edge_hop.lift_m);
  board_->SetFinger(f, Role::kFree, Primitive::kPosition, &lifted);
  explore_.hop = Hop::kLift;
  explore_.hop_since = board_->now;
  board_->reached[f] = false;
  board_->out.changed = true;
}

bool Gait::HopsOverEdge(int f) const {
  const EdgeHopParams& hop = params_.edge_hop;
  const FingerView& v = board_->view.fingers[f];
  if (!hop.enabled || board_->edges.empty() || !v.SensesPoint()) return false;
  std::vector<Edge> edges;
  for (const Blackboard::FeltEdge& e : board_->edges) edges.push_back(e.edge);
  const Eigen::Isometry3d to_object = board_->view.object.inverse();
  return EdgeOnTheWay(to_object * v.contact, to_object * explore_.target, edges, hop.reach_m) >= 0;
}

Eigen::Vector3d Gait::OverTarget() const {
  const Eigen::Vector3d centre = board_->view.object.translation();
  const Eigen::Matrix3d to_palm = board_->view.object.linear();
  Eigen::Vector3d out = explore_.target - centre;
  const SurfacePoint felt = board_->surface.Along(to_palm.transpose() * out);
  if (felt.known) out = to_palm * felt.normal;
  return explore_.target + params_.edge_hop.lift_m * out.normalized();
}

bool Gait::TickHop() {
  if (explorer_ < 0 || explore_.hop == Hop::kNone) return false;
  const EdgeHopParams& hop = params_.edge_hop;
  const int f = explorer_;
  const double since = board_->now - explore_.hop_since;
  const bool moved = board_->reached[f] || since > hop.move_timeout_s;
  switch (explore_.hop) {
    case Hop::kNone:
      return false;
    case Hop::kEase:
      if (since >= hop.ease_s) LiftExplorer();
      return true;
    case Hop::kLift:
      if (!moved) return true;
      // Lifted off a link: its point is where it was on the object, which the link may have
      // pushed away.
      if (explore_.link_lifts > 0) {
        const Eigen::Isometry3d carried = board_->view.object * explore_.object.inverse();
        explore_.point = carried * explore_.point;
        explore_.target = carried * explore_.target;
        explore_.object = board_->view.object;
      }
      {
        const Eigen::Vector3d over = OverTarget();
        board_->SetFinger(f, Role::kFree, Primitive::kPosition, &over);
      }
      explore_.hop = Hop::kOver;
      break;
    case Hop::kOver:
      if (!moved) return true;
      board_->SetFinger(f, Role::kExplore, Primitive::kHybrid, &explore_.target,
                        params_.explore_force_n);
      explore_.hop = Hop::kNone;
      break;
  }
  board_->reached[f] = false;
  explore_.hop_since = board_->now;
  board_->out.changed = true;
  return explore_.hop != Hop::kNone;
}

void Gait::TickRotate(double in_phase) {
  const ControllerView& view = board_->view;
  if (StartDeferredTurn(in_phase)) return;
  NoteStruckFingers();
  // A turn that began with a grip waits for the grasp to be stable too (as a grip would).
  const bool gripped = !regrasp_.gripping_while_turning() || GripDue(in_phase);
  if (StepDone(in_phase) && gripped) {
    if (!board_->MotionDone()) {
      board_->Note("step settled " + std::to_string(view.tracking_error_rad) + " rad short");
    }
    if (!view.grasp_stable && regrasp_.gripping_while_turning()) {
      board_->Note("no stable grasp within the grip timeout; going on");
    }
    // A finger that sat the turn out is placed again before anyone else explores.
    if (lifted_ >= 0) regrasp_.set_next_explorer(board_->fingers[lifted_]);
    regrasp_.Process(RegraspEvent::RotateDone);
  } else if (in_phase > spec_.rotate_timeout_s) {
    report_(GaitReport::kSlipped, "a rotation step did not finish within " +
                                      std::to_string(spec_.rotate_timeout_s) + " s");
  }
}

void Gait::TickGrip(double in_phase) {
  // Wait for a stable grasp (at least a moment after the role change).
  if (GripDue(in_phase)) {
    if (!board_->view.grasp_stable) board_->Note("no stable grasp within the grip timeout; going on");
    regrasp_.Process(RegraspEvent::GripStable);
  }
}

}  // namespace dmpl
