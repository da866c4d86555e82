#pragma once
// Finger gaiting: the regrasp chart (Fig. 4) and what its actions mean for the fingers (explore,
// rotate, grip), the steps toward the task's angle or its goal orientations, and the state of
// the explore under way. The supervisor starts, resumes and aborts it and ticks it while the
// grasp chart is in Tasks; the gait reports through `report` (a goal reached, the task done or
// failed, a slip), as a Boost.SML action is handed what it acts on.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "supervisor/blackboard.h"
#include "supervisor/contact_chooser.h"
#include "supervisor/gait_geometry.h"
#include "supervisor/goal_planner.h"
#include "supervisor/object_goal.h"
#include "supervisor/regrasp_chart.h"
#include "supervisor/supervisor_params.h"
#include "supervisor/task_description.h"

namespace dmpl {

// What the gait tells the supervisor that runs it (with a reason, for failures and slips).
enum class GaitReport { kGoalReached, kDone, kFailed, kSlipped };

class Gait : private RegraspActions {
 public:
  using Report = std::function<void(GaitReport, const std::string& reason)>;
  // `seed`: the run's (random goals); `chooser` (may be null: the gait's points as they are)
  // places each explorer on the felt surface (params.contact_choice). The pointers and
  // references must outlive the gait.
  Gait(Blackboard* board, ObjectGoal* goal, const GaitSpec& spec, const TaskParams& params,
       uint64_t seed, Report report, const ContactChooser* chooser = nullptr);

  void Start();   // a gait task begins, all fingers gripping
  void Resume();  // after a recovery, all fingers gripping
  void Abort();   // a contingency: back to all-grip without finishing the step
  void Tick();    // once per tick while the grasp chart is in Tasks
  void LocalRotate() { regrasp_.Process(RegraspEvent::LocalRotate); }  // A1, in a local task
  // The reference's speed in the step under way.
  double StepSpeed() const;

  const RegraspChart& chart() const { return regrasp_; }
  void set_log(sc::StateMachine<RegraspState, RegraspEvent>::Log log) {
    regrasp_.set_log(std::move(log));
  }
  const GoalSequence& goals() const { return goals_; }

 private:
  // RegraspActions.
  void Explore(const std::string& finger) override;
  void Rotate(const std::vector<std::string>& grippers) override;
  void Grip(const std::string& finger) override;
  void Finish() override { done_ = true; }
  bool GoalReached() const override;
  bool CanTurnWithout(const std::string& finger) const override;

  void StartGoals();
  bool TickGoals();  // false: the gait failed (a goal timed out)
  void TickExplore(double in_phase);
  void TickRotate(double in_phase);
  void TickGrip(double in_phase);
  // Explore: how far back (signed, about `axis`) the explorer goes: where it can follow the
  // steps it turns with until it explores again, half of them behind its home, half ahead.
  double ExploreBack(int f, const Eigen::Vector3d& axis, double sign, bool four) const;
  // While a finger explores: its point moved again by KeepClear from where the finger it slides
  // toward is now (and the rest of the step it will still turn).
  void KeepExplorerClear();
  Eigen::Vector3d StepAxis() const;  // the axis the next step turns about
  double StepSize() const;           // the task's step, or less (GaitGeometry::StepLimit)
  bool StepDone(double in_phase) const;
  // The next explorer for a step of `step` about `axis` (task.explorer_support,
  // explorer_choice.h), asked again each tick until the next explore while the grasp is not
  // known yet (a finger that just explored reads no point for a moment).
  void ChooseNextExplorer(const Eigen::Vector3d& axis, double step, int skip);
  // Whether finger `f` may stay gripping through `step` about `axis` (explorer_support.check_ride:
  // ContactChooser::Ride within its margins); `why` says why not.
  bool FurthestMayRide(const Eigen::Vector3d& axis, double step, int f, std::string* why) const;
  // params.max_contact_angle_rad: the finger (not `skip`) that touched with a link since it
  // explored, else the one touching furthest beyond the angle, explores next.
  void PreferFingerAtRisk(int skip);
  // `step` (signed, about `axis`), or the part of it that keeps the riding fingers' links out of
  // the felt surface (params.contact_choice.clear_steps); the finger that stops it explores next.
  double StepClearOfLinks(const Eigen::Vector3d& axis, double step);
  // The explorer `f`'s `point`, or the ContactChooser's choice around it for the turn it rides
  // next (`rides` steps about `axis`, by `sign`); `why` says why, when it is another point.
  Eigen::Vector3d ChooseContact(int f, const Eigen::Vector3d& point, const Eigen::Vector3d& axis,
                                double sign, double rides, std::string* why);
  // task.struck_fingers: while a step turns, the grip fingers whose links touch are marked (at a
  // later turn's start one of them is lifted off if the others hold enough without it).
  void NoteStruckFingers();
  // The finger just placed again grips with the object held still: this step is 0.
  void HoldStillForPlacedBack();
  // What a grasp is taken to hold (task.support), with the friction observed so far.
  SupportLimits SupportLimitsNow() const;
  // N: the support below which the next explorer is chosen by support (task.explorer_support).
  double SupportNeeded() const;
  // A struck finger (not `skip`) the others can do without (-1: none); lift it off.
  int StruckFingerToLift(int skip) const;
  void LiftOff(int f);
  // Starts the step's `turn`, lifting a struck finger first (once the finger gripping now
  // holds, if it grips while turning).
  void TurnOrSitOut(std::function<void()> turn);
  // A turn waiting for a grip before a struck finger lifts: starts it when due (true: waiting
  // or just started).
  bool StartDeferredTurn(double in_phase);
  // The finger that grips now holds (a stable grasp a moment after the role change), or has had
  // the grip's time.
  bool GripDue(double in_phase) const;
  bool LimitDeviation() const {
    return params_.has_goals() && params_.max_finger_deviation_rad > 0;
  }

  // params.face_bounds: the explorer's `point` (its tip's centre, palm frame), or where it stands
  // face_bounds.margin_m inside its felt face (face_bounds.h) once the object has the
  // orientation `landing` it will have when the explorer lands; `why` says so when it moved.
  Eigen::Vector3d KeepOnFace(const Eigen::Vector3d& point, const Eigen::Matrix3d& landing,
                             std::string* why) const;

  // params.edge_hop: whether the explorer's way from its contact to its target crosses a felt
  // edge (edge_hop.h); if so it eases, is lifted and moved over its point first.
  bool HopsOverEdge(int f) const;
  // One tick of that hop: true while the explorer is not yet brought in to its point.
  bool TickHop();
  // An explorer on its link with its tip off the surface is lifted off to come again
  // (task.explorer_link); true on the tick it is.
  bool LiftOffLink();
  // The explorer lifted edge_hop.lift_m off along the line from the centre: the hop's kLift.
  void LiftExplorer();
  // Where the hop takes the explorer before it is brought in: lift_m over its target, along the
  // felt normal there (or the line from the centre where the surface is not known).
  Eigen::Vector3d OverTarget() const;

  // The explore under way: the explorer's point before KeepClear, and how to keep it clear
  // while it slides (the finger it slides toward keeps moving, and so may the object).
  enum class Hop { kNone, kEase, kLift, kOver };
  struct ExploreState {
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Isometry3d object = Eigen::Isometry3d::Identity();  // where the object was then
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // the step axis when it began
    bool spaced = false;
    bool neighbour_rides = false;
    double sign = 1.0;
    Hop hop = Hop::kNone;  // the stage of its step over an edge or off a link
    double hop_since = 0.0;
    double on_link_since = -1.0;  // its link touches, its tip does not, since (task.explorer_link)
    int link_lifts = 0;           // times lifted off its link this explore
  };

  Blackboard* board_;
  ObjectGoal* goal_;
  const GaitSpec& spec_;
  const TaskParams& params_;
  uint64_t seed_;
  Report report_;
  const ContactChooser* chooser_;
  GaitGeometry geometry_;
  GoalSequence goals_;
  double phase_since_ = 0.0;
  int explorer_ = -1;
  double step_ = 0.0;        // the rotation step under way
  double step_limit_ = 0.0;  // StepLimit at the last explore (0: none)
  ExploreState explore_;
  // ChooseNextExplorer's question while its answer waits for the grasp to be known.
  struct PendingChoice {
    bool pending = false;
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
    double step = 0.0;
    int skip = -1;
  };
  PendingChoice pending_choice_;
  // task.struck_fingers: the fingers that sit the turns out, the one lifted for the turn under
  // way (-1: none), and the one just placed again, whose grip the object waits for still.
  std::vector<bool> struck_;
  int lifted_ = -1;
  int placed_back_ = -1;
  // A turn that waits for a grip before a struck finger lifts off (null: none).
  std::function<void()> deferred_turn_;
  // Per finger: whether it stopped a step with its links (StepClearOfLinks), and was placed
  // again since.
  enum class LinkBlock { kNone, kBlocked, kPlaced };
  std::vector<LinkBlock> link_block_;
  bool done_ = false;
  RegraspChart regrasp_;
};

}  // namespace dmpl
