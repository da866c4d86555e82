#pragma once
// The supervisor's core: the grasp statechart of the paper's Fig. 5 (object held -> approach ->
// contact -> composite -> stable -> release -> tasks -> end), the tasks of a task file run in
// sequence, the regrasp statechart (Fig. 4) for finger gaiting, and the replanning the paper left
// for future work: a grip finger that loses contact, or an object that slips, pauses the motion
// and re-grips; a process that stops beating makes it hold the grasp. Pure: controller status in,
// the controller's task and simulator requests out, once per tick.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/runtime/sim_request.h"
#include "supervisor/goal_planner.h"
#include "supervisor/regrasp_chart.h"
#include "supervisor/statechart.h"
#include "supervisor/supervisor_params.h"
#include "supervisor/task_description.h"

namespace dmpl {

enum class GraspState {
  ObjectHeld, Approaching, Gripping, Releasing, Settling, Tasks, Recovering, Holding, Done, Failed
};
enum class GraspEvent {
  Start, AllTouching, GraspStable, ReleaseDue, Settled, TaskDone, TaskFailed, ContactLost, Slip,
  Recovered, ProcessLost, ProcessBack, GraspLost, Timeout
};
const char* ToString(GraspState s);
const char* ToString(GraspEvent e);
// What a grasp event carries: why (for the log, the status and the action that handles it) and
// the finger it is about.
struct GraspEventData {
  std::string reason;
  int finger = -1;  // -1: not about one finger
};

struct FingerView {
  bool in_contact = false;
  double force = 0.0;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
};

// What the supervisor reads from one controller status.
struct ControllerView {
  int64_t seq = 0;
  double time_s = 0.0;
  std::vector<FingerView> fingers;
  Eigen::Isometry3d object = Eigen::Isometry3d::Identity();  // the controller's estimate
  std::vector<ControllerEvent> events;
  bool motion_done = false;
  bool grasp_stable = false;
  double tracking_error_rad = 0.0;  // the object estimate against the controller's reference
};

struct SupervisorOutput {
  TaskInput task;                       // the controller's task for the next tick
  SimRequest sim = SimRequest::kNone;   // a simulator control to send with this tick's seq
  bool changed = false;                 // state, action or task changed this tick
};

class Supervisor : private RegraspActions {
 public:
  // `seed`: the run's seed (random goals).
  Supervisor(std::vector<std::string> fingers, TaskFile tasks, TaskParams task_params,
             SupervisorParams params, uint64_t seed = 1);

  const SupervisorOutput& Step(const ControllerView& view);
  // From the heartbeat monitor: a required process went silent (lost) or is back.
  void SetProcessLost(bool lost, const std::string& who);

  GraspState grasp_state() const { return grasp_.state(); }
  const RegraspChart& regrasp() const { return regrasp_; }
  std::string task_name() const;
  int task_index() const { return task_index_; }
  int num_tasks() const { return static_cast<int>(tasks_.tasks.size()); }
  const std::vector<std::string>& fingers() const { return fingers_; }
  std::vector<Role> roles() const;
  double rotation_commanded() const { return rotation_commanded_; }
  double rotation_goal() const { return rotation_goal_; }
  // The goal orientations of a gait (task.goals, task.random_goals); empty without.
  const GoalSequence& goals() const { return goals_; }
  int recoveries() const { return recoveries_; }
  bool holding() const { return grasp_.is(GraspState::Holding); }
  bool finished() const { return grasp_.is(GraspState::Done); }
  bool failed() const { return grasp_.is(GraspState::Failed); }
  const std::string& last_action() const { return last_action_; }
  const std::string& note() const { return note_; }
  std::string GraspChartDot() const { return grasp_.ToDot(); }
  std::string RegraspChartDot() const { return regrasp_.ToDot(); }
  std::string GraspChartMermaid() const { return grasp_.ToMermaid(); }
  std::string RegraspChartMermaid() const { return regrasp_.ToMermaid(); }
  // Every transition of both charts, as text (for logs and tests).
  const std::vector<std::string>& transitions() const { return transitions_; }

 private:
  using GraspChart = sc::StateMachine<GraspState, GraspEvent, GraspEventData>;
  GraspChart BuildGraspChart();

  // RegraspActions.
  void Explore(const std::string& finger) override;
  void Rotate(const std::vector<std::string>& grippers) override;
  void Grip(const std::string& finger) override;
  void Finish() override;
  bool GoalReached() const override;
  bool CanTurnWithout(const std::string& finger) const override;
  Eigen::Vector3d StepAxis() const;  // the axis the next step turns about
  // Whether the fingers stand around `axis` (gait.overlap_about, within overlap_max_tilt_rad).
  bool AroundFingers(const Eigen::Vector3d& axis) const;
  // The largest step the fingers' spacing around `axis` allows (gait.tip_clearance_m): between
  // two explores of a finger the one it slides back toward rides n - 1 steps toward it, so the
  // fingers' spacing (2 pi / n) must hold n - 1 steps and the angle two fingertips need at the
  // distance they stand from the axis (sensed: tips and object estimate).
  double GaitStepLimit(const Eigen::Vector3d& axis) const;
  // The explorer's point moved forward (about `axis`, by `sign`) until it keeps the clearance
  // from the finger it slides back toward, where that finger will be after `step`.
  Eigen::Vector3d KeepClear(int explorer, const Eigen::Vector3d& axis, double sign, double step,
                            bool neighbour_rides, const Eigen::Vector3d& target) const;
  double StepSize() const;           // the task's step, or less (GaitStepLimit)
  // While a finger explores: its point moved again by KeepClear from where the finger it slides
  // toward is now (and the rest of the step it will still turn).
  void KeepExplorerClear();
  double StepSpeed() const;          // the reference's speed in the step under way
  // task.max_finger_deviation_rad: the angle (about the object's centre) between finger k's home
  // and where it would be after `turn` (about the centre; sensed tip and object estimate).
  double Deviation(int k, const Eigen::AngleAxisd& turn) const;
  // The largest part of `step` about `axis` that leaves every finger that rides it (all but
  // `skip`, if any; only fingers in contact) within the deviation, or no further than it is.
  double StepWithinReach(const Eigen::Vector3d& axis, double step, int skip) const;
  // The next explorer: the finger (not `skip`) that `step` about `axis` takes furthest.
  void ChooseNextExplorer(const Eigen::Vector3d& axis, double step, int skip);
  bool LimitDeviation() const {
    return task_params_.has_goals() && task_params_.max_finger_deviation_rad > 0;
  }

  // Commands.
  void NewTask(const std::string& name);
  void SetFinger(int f, Role role, Primitive primitive, const Eigen::Vector3d* target = nullptr,
                 double force = 0.0);
  void AllGrip();
  void HoldObjectWhereItIs();
  void RotateGoal(const Eigen::Vector3d& axis, double angle);
  Eigen::Vector3d Axis(const std::string& name) const;  // x, y, z or "task" (task.axis)
  Eigen::Quaterniond SensedOrientation() const;
  void StartGoals();
  int Finger(const std::string& name) const;

  // Grasp chart actions.
  void Approach();
  void StartTask(int index);
  void PauseAndRegrip(const std::string& why);
  void Resume();
  void Hold(const std::string& why);
  void Fail(const std::string& why);

  // Per-tick work by state.
  void AdvanceClock(double sensed_s);
  void OnControllerEvents(const std::vector<ControllerEvent>& events);
  void TickGraspChart();
  void TickRecovery();
  void TickApproach();
  void TickLocalTask();
  void TickGait();
  void TickGoals();
  bool StepDone(double in_phase) const;
  bool ConditionHolds(Condition c, int finger) const;
  // Whether `finger`, playing `role`, is in `state` (a PTask's entry or exit FIstate).
  bool InState(const FIstate& state, int finger, Role role) const;
  void Note(const std::string& text);

  uint64_t seed_;
  std::vector<std::string> fingers_;
  TaskFile tasks_;
  TaskParams task_params_;
  SupervisorParams params_;
  SupervisorOutput out_;
  ControllerView view_;
  double now_ = 0.0;             // the sensed clock less the gaps in it (AdvanceClock)
  double last_sensed_s_ = -1.0;  // the sensed clock at the last report
  double unseen_s_ = 0.0;        // the gaps in the sensed clock so far
  double state_since_ = 0.0;
  int32_t next_task_id_ = 1;

  // The commanded object goal (palm frame).
  bool has_goal_ = false;
  Eigen::Isometry3d goal_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d start_pose_ = Eigen::Isometry3d::Identity();
  double rotation_commanded_ = 0.0;
  double rotation_goal_ = 0.0;
  double rotation_at_task_start_ = 0.0;

  // Grasp.
  std::vector<int> extensions_;
  std::vector<bool> touched_;
  std::vector<bool> reached_;
  double stable_at_ = -1.0;

  // Tasks.
  int task_index_ = -1;
  double task_since_ = 0.0;
  std::vector<int> ptask_index_;
  std::vector<double> ptask_since_;
  bool motion_done_event_ = false;
  std::vector<Eigen::Vector3d> home_;
  Eigen::Vector3d home_centre_ = Eigen::Vector3d::Zero();
  double phase_since_ = 0.0;
  int explorer_ = -1;
  double step_ = 0.0;  // the rotation step under way
  double step_limit_ = 0.0;  // GaitStepLimit at the last explore (0: none)
  Eigen::Vector3d explore_target_ = Eigen::Vector3d::Zero();
  // The explorer's point before KeepClear, and how to keep it clear while it slides (the
  // finger it slides toward keeps moving, and so may the object).
  Eigen::Vector3d explore_point_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d explore_axis_ = Eigen::Vector3d::UnitX();  // the step axis when it began
  bool explore_spaced_ = false;
  bool explore_neighbour_rides_ = false;
  double explore_sign_ = 1.0;
  bool gait_done_ = false;
  GoalSequence goals_;

  // Contingencies.
  // A finger placed again in a recovery (params_.replace_after_s): lifting, moving over to its
  // home, or coming in.
  enum class Replace { kNone, kLift, kOver, kIn };
  void TickReplace();
  std::vector<Replace> replace_;
  std::vector<double> replace_since_;
  int recoveries_ = 0;
  // Recoveries that count against supervisor.max_recoveries: since the start, or since the last
  // goal orientation reached (a goal reached after them is progress, not a grasp going bad).
  int recoveries_counted_ = 0;
  bool process_lost_ = false;
  bool stop_sent_ = false;
  bool release_sent_ = false;

  std::string last_action_;
  std::string note_;
  std::vector<std::string> transitions_;
  RegraspChart regrasp_;
  GraspChart grasp_;
};

}  // namespace dmpl
