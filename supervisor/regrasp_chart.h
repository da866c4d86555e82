#pragma once
// The regrasp statechart of the paper's Fig. 4: states S1-S5 (who grips, who explores) and
// actions A1-A13. Every role change passes through S1; the fingers explore in a configured order
// (the paper's R, M, F, T), each time the other three turn the object by one step. The chart
// decides; what an action means for the fingers is up to the RegraspActions it is given.
//
// Two ways to turn. kThreeFingers is the paper's: the explorer keeps a light contact while the
// other three turn the object under it (A2/A5/A8/A11). kFourFingers uses only rows the paper also
// has: the explorer moves while three hold the object still, grips again (back in S1), and then
// all four turn it (A1). Four contacts around the object keep its position under control while it
// turns; three leave a half-circle open on the explorer's side. kContinuous overlaps the paper's
// two phases: the three grippers turn the object while the explorer slides back (A4 and A2 at
// once), so the object never waits for an explorer; the explorer grips again when both are done.
// kAuto decides at each explore (RegraspActions::CanTurnWithout): continuous when the three
// grippers can turn the object about the step's axis without the explorer, else four.
//
// With `grip_turns` the four-finger turn (A1) does not wait for the grip: the finger that just
// explored grips while all four turn (A3/A6/A9/A12 and A1 at once), and the step counts done when
// the object has turned and the grasp is stable (RegraspActions' caller decides both). The grip
// and the turn then cost the longer of the two instead of their sum.
#include <string>
#include <vector>

#include "supervisor/statechart.h"
#include "supervisor/turn_mode.h"

namespace dmpl {

enum class RegraspState { S1, S2, S3, S4, S5 };
enum class RegraspEvent {
  Begin,         // a gait (or a local rotation) starts, all four fingers gripping
  LocalRotate,   // a local rotation with all four fingers
  ExploreReady,  // the exploring finger is at its new contact point
  RotateDone,    // the object reached the step's goal
  GripStable,    // the grasp is stable with the finger that just switched to grip
  Abort,         // a contingency: back to all-grip without finishing the step
};

const char* ToString(RegraspState s);
const char* ToString(RegraspEvent e);

// What the chart asks for. `finger` is the name of the exploring or gripping finger; `grippers`
// the fingers that turn the object, in the hand's order.
class RegraspActions {
 public:
  virtual ~RegraspActions() = default;
  virtual void Explore(const std::string& finger) = 0;              // A4, A7, A10, A13
  virtual void Rotate(const std::vector<std::string>& grippers) = 0;  // A1, A2, A5, A8, A11
  virtual void Grip(const std::string& finger) = 0;                 // A3, A6, A9, A12
  virtual void Finish() = 0;                                        // the goal is reached
  virtual bool GoalReached() const = 0;
  // kAuto: can the other three turn the object about the next step's axis while `finger`
  // explores?
  virtual bool CanTurnWithout(const std::string& finger) const = 0;
};

class RegraspChart {
 public:
  // The paper's chart has one explore state per finger (S2..S5) for its four-finger hand.
  static constexpr int kFingers = 4;
  using Turn = TurnMode;  // task.turn (turn_mode.h)
  // `fingers`: the hand's finger names, in the hand's order; `order`: the exploring order, each
  // finger once (S2..S5 = order[0..3]).
  RegraspChart(RegraspActions* actions, std::vector<std::string> fingers,
               std::vector<std::string> order, Turn turn = Turn::kThreeFingers,
               bool grip_turns = false);

  bool Process(RegraspEvent e) { return chart_.Process(e); }
  bool is(RegraspState s) const { return chart_.is(s); }
  RegraspState state() const { return chart_.state(); }
  const std::string& last_action() const { return last_action_; }
  const std::string& next_explorer() const { return order_[next_]; }
  // Who explores next (one of the fingers): instead of the next in the order.
  void set_next_explorer(const std::string& finger);
  int regrasps() const { return regrasps_; }
  bool rotating() const { return phase_ == Phase::kRotating; }
  bool exploring() const { return phase_ == Phase::kExploring; }
  // The step under way turns the object while the explorer slides (kContinuous, or kAuto's
  // choice at the last explore).
  bool overlapping() const { return overlapping_; }
  // The turn under way began with a grip (grip_turns): it is done when the grasp is stable too.
  bool gripping_while_turning() const { return phase_ == Phase::kRotating && grip_turning_; }
  Turn turn() const { return turn_; }
  std::string ToDot() const { return chart_.ToDot(); }
  std::string ToMermaid() const { return chart_.ToMermaid(); }
  void set_log(sc::StateMachine<RegraspState, RegraspEvent>::Log log) {
    chart_.set_log(std::move(log));
  }

 private:
  enum class Phase { kGripping, kExploring, kRotating };
  using Row = sc::StateMachine<RegraspState, RegraspEvent>::Row;
  sc::StateMachine<RegraspState, RegraspEvent> Build();
  std::vector<Row> AllGripRows();
  void AddFingerRows(int k, std::vector<Row>* rows);
  sc::Action AllRotateAction();
  sc::Guard NextIs(int k);
  sc::Action ExploreAction(int number, int k);
  sc::Action RotateAction(int number, int k);
  sc::Action GripAction(int number, int k);
  std::vector<std::string> Grippers(int k) const;  // all fingers but order_[k]
  static std::string Names(const std::vector<std::string>& fingers);  // "TFM"

  RegraspActions* actions_;
  std::vector<std::string> fingers_;
  std::vector<std::string> order_;
  Turn turn_;
  int next_ = 0;
  int regrasps_ = 0;
  bool overlapping_ = false;
  bool grip_turns_ = false;
  bool grip_turning_ = false;  // the step under way began with a grip
  Phase phase_ = Phase::kGripping;
  std::string last_action_;
  sc::StateMachine<RegraspState, RegraspEvent> chart_;
};

}  // namespace dmpl
