#pragma once
// A local task of a task file (a CTask that is not a gait): each finger through its PTask
// sequence (FIstate checks at entry and exit, transition conditions) while the object moves as
// the task says. The supervisor starts, resumes and ticks it; it reports through `report`.
#include <functional>
#include <string>
#include <vector>

#include "supervisor/blackboard.h"
#include "supervisor/object_goal.h"
#include "supervisor/supervisor_params.h"
#include "supervisor/task_description.h"

namespace dmpl {

class LocalTask {
 public:
  using Report = std::function<void(GraspEvent, const GraspEventData&)>;
  // `all_turn`: a motion that all four fingers grip through begins (the regrasp chart's A1).
  // The references must outlive the task.
  LocalTask(Blackboard* board, ObjectGoal* goal, const TaskParams& params, Report report,
            std::function<void()> all_turn);

  // Starts `task` (any task: the per-task clocks restart); for a local one, each finger's first
  // PTask and the object motion at `speed` rad/s.
  void Start(const CTask& task, double speed);
  // After a recovery: starts over toward the goal it had; what was already turned counts.
  void Resume(const CTask& task, double speed);
  void Tick(const CTask& task);

 private:
  void StartMotion(const CTask& task, double speed);
  // The sequence `task` gives finger f (its own, or "all"'s); null: none.
  const std::vector<PTask>* Sequence(const CTask& task, int f) const;
  void Enter(int f, const PTask& p);  // the finger's role, primitive, target and force
  bool ConditionHolds(Condition c, int finger) const;
  // Whether `finger`, playing `role`, is in `state` (a PTask's entry or exit FIstate).
  bool InState(const FIstate& state, int finger, Role role) const;
  Eigen::Vector3d Axis(const std::string& name) const;  // x, y, z or "task" (task.axis)

  Blackboard* board_;
  ObjectGoal* goal_;
  const TaskParams& params_;
  Report report_;
  std::function<void()> all_turn_;
  double since_ = 0.0;
  double rotation_at_start_ = 0.0;
  std::vector<int> ptask_index_;
  std::vector<double> ptask_since_;
};

}  // namespace dmpl
