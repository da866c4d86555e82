#include "supervisor/regrasp_chart.h"

#include <algorithm>

#include "components/runtime/check.h"

namespace dmpl {

const char* ToString(RegraspState s) {
  switch (s) {
    case RegraspState::S1: return "S1";
    case RegraspState::S2: return "S2";
    case RegraspState::S3: return "S3";
    case RegraspState::S4: return "S4";
    case RegraspState::S5: return "S5";
  }
  return "?";
}

const char* ToString(RegraspEvent e) {
  switch (e) {
    case RegraspEvent::Begin: return "Begin";
    case RegraspEvent::LocalRotate: return "LocalRotate";
    case RegraspEvent::ExploreReady: return "ExploreReady";
    case RegraspEvent::RotateDone: return "RotateDone";
    case RegraspEvent::GripStable: return "GripStable";
    case RegraspEvent::Abort: return "Abort";
  }
  return "?";
}

namespace {
constexpr RegraspState kExploreState[RegraspChart::kFingers] = {
    RegraspState::S2, RegraspState::S3, RegraspState::S4, RegraspState::S5};
}  // namespace

RegraspChart::RegraspChart(RegraspActions* actions, std::vector<std::string> fingers,
                           std::vector<std::string> order, Turn turn, bool grip_turns)
    : actions_(actions),
      fingers_(std::move(fingers)),
      order_(std::move(order)),
      turn_(turn),
      grip_turns_(grip_turns),
      chart_(Build()) {
  DMPL_DEMAND(actions_ != nullptr);
  DMPL_DEMAND(fingers_.size() == kFingers);
  DMPL_DEMAND(std::is_permutation(order_.begin(), order_.end(), fingers_.begin(), fingers_.end()));
}

void RegraspChart::set_next_explorer(const std::string& finger) {
  const auto it = std::find(order_.begin(), order_.end(), finger);
  DMPL_DEMAND(it != order_.end());
  next_ = static_cast<int>(it - order_.begin());
}

std::vector<std::string> RegraspChart::Grippers(int k) const {
  std::vector<std::string> out;
  for (const std::string& f : fingers_) {
    if (f != order_[k]) out.push_back(f);
  }
  return out;
}

std::string RegraspChart::Names(const std::vector<std::string>& fingers) {
  // One-letter names read as the paper writes them ("TFM"); longer ones are listed.
  const bool letters = std::all_of(fingers.begin(), fingers.end(),
                                   [](const std::string& f) { return f.size() == 1; });
  std::string out;
  for (const std::string& f : fingers) out += (out.empty() || letters ? "" : ",") + f;
  return out;
}

sc::Guard RegraspChart::NextIs(int k) {
  return sc::Guard("next is " + order_[k] + ", goal not reached",
                   [this, k] { return next_ == k && !actions_->GoalReached(); });
}

// The paper numbers the actions per finger: explore 4, 7, 10, 13; rotate 2, 5, 8, 11; grip 3, 6,
// 9, 12 for the fingers in exploring order R, M, F, T (S2..S5).
sc::Action RegraspChart::ExploreAction(int number, int k) {
  const std::string explore = "A" + std::to_string(number) + " " + order_[k] + " explore";
  const std::string both = explore + " + A" + std::to_string(number - 2) + " " + Names(Grippers(k)) +
                           " rotate";
  const std::string name = turn_ == Turn::kContinuous ? both
                           : turn_ == Turn::kAuto     ? explore + " (+ A" +
                                                        std::to_string(number - 2) + " rotate)"
                                                      : explore;
  return sc::Action(name, [this, k, explore, both] {
    overlapping_ = turn_ == Turn::kContinuous ||
                   (turn_ == Turn::kAuto && actions_->CanTurnWithout(order_[k]));
    last_action_ = overlapping_ ? both : explore;
    phase_ = Phase::kExploring;
    grip_turning_ = false;
    actions_->Explore(order_[k]);
    if (overlapping_) actions_->Rotate(Grippers(k));
  });
}

sc::Action RegraspChart::RotateAction(int number, int k) {
  const std::vector<std::string> grippers = Grippers(k);
  const std::string name = "A" + std::to_string(number) + " " + Names(grippers) + " rotate";
  return sc::Action(name, [this, grippers, name] {
    last_action_ = name;
    phase_ = Phase::kRotating;
    grip_turning_ = false;
    actions_->Rotate(grippers);
  });
}

sc::Action RegraspChart::GripAction(int number, int k) {
  const std::string grip = "A" + std::to_string(number) + " " + order_[k] + " grip";
  // After an explore that did not turn the object, all four turn it next (A1): with grip_turns
  // at once, while the explorer grips.
  const bool four = turn_ == Turn::kFourFingers, autom = turn_ == Turn::kAuto;
  const std::string both = grip + " + A1 " + Names(fingers_) + " rotate";
  const std::string name = !grip_turns_ || !(four || autom) ? grip
                           : four                          ? both
                                                           : grip + " (+ A1 rotate)";
  return sc::Action(name, [this, k, grip, both, four, autom] {
    grip_turning_ = grip_turns_ && (four || (autom && !overlapping_));
    last_action_ = grip_turning_ ? both : grip;
    phase_ = grip_turning_ ? Phase::kRotating : Phase::kGripping;
    ++regrasps_;
    next_ = (k + 1) % kFingers;
    actions_->Grip(order_[k]);
    if (grip_turning_) actions_->Rotate(fingers_);
  });
}

sc::StateMachine<RegraspState, RegraspEvent> RegraspChart::Build() {
  std::vector<Row> rows = AllGripRows();
  for (int k = 0; k < kFingers; ++k) AddFingerRows(k, &rows);
  return sc::StateMachine<RegraspState, RegraspEvent>("regrasp", RegraspState::S1,
                                                      std::move(rows));
}

sc::Action RegraspChart::AllRotateAction() {
  const std::string name = "A1 " + Names(fingers_) + " rotate";
  return sc::Action(name, [this, name] {
    last_action_ = name;
    phase_ = Phase::kRotating;
    grip_turning_ = false;
    actions_->Rotate(fingers_);
  });
}

// S1's rows before the fingers' own: a local rotation with all four, the goal reached, and
// (four, auto) the turn with all four after a grip.
std::vector<RegraspChart::Row> RegraspChart::AllGripRows() {
  using S = RegraspState;
  using E = RegraspEvent;
  const sc::Guard goal("goal reached", [this] { return actions_->GoalReached(); });
  const sc::Action finish("finish", [this] {
    last_action_ = "finish";
    phase_ = Phase::kGripping;
    actions_->Finish();
  });
  std::vector<Row> rows = {
      // from   event            guard   action  to
      {S::S1, E::LocalRotate, sc::kAlways, AllRotateAction(), S::S1},
      {S::S1, E::Begin, goal, finish, S::S1},
      {S::S1, E::GripStable, goal, finish, S::S1},
  };
  if (turn_ == Turn::kFourFingers) {
    // explore (three hold) -> grip -> all four turn -> the next finger explores.
    const sc::Guard gripping("gripping", [this] { return phase_ == Phase::kGripping; });
    rows.push_back({S::S1, E::RotateDone, goal, finish, S::S1});
    rows.push_back({S::S1, E::GripStable, gripping, AllRotateAction(), S::S1});
  }
  if (turn_ == Turn::kAuto) {
    // As four, but after an explore that turned the object too the next finger explores.
    const sc::Guard after_four("gripping, the step not turned", [this] {
      return phase_ == Phase::kGripping && !overlapping_;
    });
    rows.push_back({S::S1, E::RotateDone, goal, finish, S::S1});
    rows.push_back({S::S1, E::GripStable, after_four, AllRotateAction(), S::S1});
  }
  return rows;
}

// The rows of the k-th finger in the exploring order: from S1 into its explore state and back.
void RegraspChart::AddFingerRows(int k, std::vector<Row>* rows) {
  using S = RegraspState;
  using E = RegraspEvent;
  const bool four = turn_ == Turn::kFourFingers, autom = turn_ == Turn::kAuto;
  const sc::Guard exploring("exploring", [this] { return phase_ == Phase::kExploring; });
  const sc::Guard rotating("rotating", [this] { return phase_ == Phase::kRotating; });
  const sc::Action abort("abort step", [this] {
    last_action_ = "abort step";
    phase_ = Phase::kGripping;
  });
  const S sk = kExploreState[k];
  rows->push_back({S::S1, E::Begin, NextIs(k), ExploreAction(4 + 3 * k, k), sk});
  // What ends S1 for the next explorer: a step's turn with four, a grip with three.
  if (four || autom) {
    rows->push_back({S::S1, E::RotateDone, NextIs(k), ExploreAction(4 + 3 * k, k), sk});
  }
  if (!four) {
    // Not while a grip turns the object with all four (grip_turns): that ends with RotateDone.
    const sc::Guard next = NextIs(k);
    const sc::Guard after_grip(next.name, [this, next] {
      return !(phase_ == Phase::kRotating && grip_turning_) && next.fn();
    });
    rows->push_back({S::S1, E::GripStable, after_grip, ExploreAction(4 + 3 * k, k), sk});
  }
  if (turn_ == Turn::kThreeFingers) {
    rows->push_back({sk, E::ExploreReady, exploring, RotateAction(2 + 3 * k, k), sk});
    rows->push_back({sk, E::RotateDone, rotating, GripAction(3 + 3 * k, k), S::S1});
  } else {
    // Four: the explorer is at its point; continuous: and the step's turn is done too.
    rows->push_back({sk, E::ExploreReady, exploring, GripAction(3 + 3 * k, k), S::S1});
  }
  rows->push_back({sk, E::Abort, sc::kAlways, abort, S::S1});
}

}  // namespace dmpl
