#pragma once
// The supervisor's core: the grasp statechart of the paper's Fig. 5 (object held -> approach ->
// contact -> composite -> stable -> release -> tasks -> end), the tasks of a task file run in
// sequence, and the replanning the paper left for future work: a grip finger that loses
// contact, or an object that slips, pauses the motion and re-grips; a process that stops
// beating makes it hold the grasp. Pure: controller status in, the controller's task and
// simulator requests out, once per tick.
//
// Its parts share a Blackboard (what the controller said, the task going out) and the
// ObjectGoal: the Gait (the regrasp chart of Fig. 4 and finger gaiting), the LocalTask (PTask
// sequences) and the FingerReplacer (recoveries). The supervisor keeps the grasp chart and the
// task file, and hands each part what it acts on, as Boost.SML injects an action's
// dependencies.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "components/runtime/sensed_clock.h"
#include "supervisor/blackboard.h"
#include "supervisor/finger_replacer.h"
#include "supervisor/gait.h"
#include "supervisor/local_task.h"
#include "supervisor/object_goal.h"
#include "supervisor/statechart.h"
#include "supervisor/supervisor_params.h"
#include "supervisor/supervisor_types.h"
#include "supervisor/task_description.h"

namespace dmpl {

class Supervisor {
 public:
  // `seed`: the run's seed (random goals); `chooser`: the explorer's contacts on the felt
  // surface (task.contact_choice; null: off).
  Supervisor(std::vector<std::string> fingers, TaskFile tasks, TaskParams task_params,
             SupervisorParams params, uint64_t seed = 1,
             std::shared_ptr<const ContactChooser> chooser = nullptr);
  Supervisor(const Supervisor&) = delete;  // its parts point at its members
  Supervisor& operator=(const Supervisor&) = delete;

  const SupervisorOutput& Step(const ControllerView& view);
  // From the heartbeat monitor: a required process went silent (lost) or is back.
  void SetProcessLost(bool lost, const std::string& who);

  GraspState grasp_state() const { return grasp_.state(); }
  const RegraspChart& regrasp() const { return gait_.chart(); }
  std::string task_name() const;
  int task_index() const { return task_index_; }
  int num_tasks() const { return static_cast<int>(tasks_.tasks.size()); }
  const std::vector<std::string>& fingers() const { return board_.fingers; }
  std::vector<Role> roles() const;
  double rotation_commanded() const { return goal_.commanded(); }
  double rotation_goal() const { return goal_.to_command(); }
  // The goal orientations of a gait (task.goals, task.random_goals); empty without.
  const GoalSequence& goals() const { return gait_.goals(); }
  int recoveries() const { return recoveries_; }
  bool holding() const { return grasp_.is(GraspState::Holding); }
  bool finished() const { return grasp_.is(GraspState::Done); }
  bool failed() const { return grasp_.is(GraspState::Failed); }
  const std::string& last_action() const { return last_action_; }
  const std::string& note() const { return board_.note; }
  std::string GraspChartDot() const { return grasp_.ToDot(); }
  std::string RegraspChartDot() const { return gait_.chart().ToDot(); }
  std::string GraspChartMermaid() const { return grasp_.ToMermaid(); }
  std::string RegraspChartMermaid() const { return gait_.chart().ToMermaid(); }
  // Every transition of both charts, as text (for logs and tests).
  const std::vector<std::string>& transitions() const { return transitions_; }

 private:
  using GraspChart = sc::StateMachine<GraspState, GraspEvent, GraspEventData>;
  struct GraspChartActions;
  GraspChart BuildGraspChart();
  GraspChartActions MakeGraspChartActions();
  void LogTransitions();

  // Grasp chart actions.
  void Approach();
  void BeginTasks();
  void StartTask(int index);
  void PauseAndRegrip(const std::string& why);
  void Resume();
  void Hold(const std::string& why);
  void Fail(const std::string& why);
  void Finish();

  // Per tick.
  void AdvanceClock(double sensed_s);
  void OnControllerEvents(const std::vector<ControllerEvent>& events);
  void OnGaitReport(GaitReport report, const std::string& reason);
  void TickGraspChart();
  void TickApproach();
  void ReachFurther(int f);
  void TickRecovery();
  void TickEnded();
  bool InState(GraspState s, double longer_than_s) const;
  const CTask& task() const { return tasks_.tasks[task_index_]; }
  bool CheckLinkRest();  // a grip finger on its link too long: recover (true)
  bool GaitUnderWay() const;
  // task.face_surface: on each new task, which touching fingers the hand model puts with a link
  // near the felt surface, each asked to turn its tip's front toward it.
  void AskFacing();

  std::shared_ptr<const ContactChooser> chooser_;  // before the gait that points at it
  TaskFile tasks_;
  TaskParams task_params_;
  SupervisorParams params_;
  Blackboard board_;
  SensedClock clock_;
  ObjectGoal goal_;
  Gait gait_;
  LocalTask local_;
  FingerReplacer replacer_;
  double state_since_ = 0.0;      // when the grasp chart entered its state
  std::vector<int> extensions_;   // approach: how often each finger reached further in
  double stable_at_ = -1.0;       // the grasp was stable (the release is timed from it)
  int task_index_ = -1;
  int32_t facing_task_id_ = 0;    // the task AskFacing last looked at
  int recoveries_ = 0;
  // Recoveries that count against supervisor.max_recoveries: since the start, or since the last
  // goal orientation reached (a goal reached after them is progress, not a grasp going bad).
  int recoveries_counted_ = 0;
  bool process_lost_ = false;
  bool stop_sent_ = false;
  double stop_sent_at_ = 0.0;
  bool release_sent_ = false;
  std::string last_action_;
  std::vector<std::string> transitions_;
  GraspChart grasp_;
};

}  // namespace dmpl
