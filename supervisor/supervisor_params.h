#pragma once
#include <string>
#include <vector>

#include "components/runtime/params.h"

namespace dmpl {

// Section `task`: what to do. The structure is in the task file; these are its numbers, so that
// `--set task.axis=y` or `--set task.angle=3.14` change an experiment without editing files.
struct TaskParams {
  std::string file = "configs/tasks/fig8_rotate.yaml";  // relative paths: from $DMPL_ROOT
  std::string axis = "x";               // rotation axis in the palm frame: x, y or z
  double angle = 0.2;                   // rad: the task's angle (local rotation, or the gait's goal)
  double step = 0.17453292519943295;    // rad: one gait step (the paper's 10 deg)
  // Who turns the object in a gait: "three" (the paper's A2..A11: three turn while the explorer
  // slides) or "four" (the explorer moves while three hold still, grips again, then all four
  // turn: A1). See RegraspChart.
  std::string turn = "three";
  double angular_speed = 0.25;          // rad/s of the object reference
  double explore_force_n = 0.1;         // the exploration finger's force (the paper's 0.1 N)
  double explore_travel = 1.0;          // the explorer goes back (steps it rides) / 2 * step * this

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(file));
    a->Visit(DMPL_NVP(axis));
    a->Visit(DMPL_NVP(angle));
    a->Visit(DMPL_NVP(step));
    a->Visit(DMPL_NVP(turn));
    a->Visit(DMPL_NVP(angular_speed));
    a->Visit(DMPL_NVP(explore_force_n));
    a->Visit(DMPL_NVP(explore_travel));
  }
  void Validate(const std::string& source) const;
};

// Section `supervisor`: how to watch over it.
struct SupervisorParams {
  std::vector<std::string> required_processes = {"dmpl_sim", "dmpl_noise", "dmpl_ik",
                                                 "dmpl_controller"};
  double heartbeat_timeout_s = 2.0;     // wall clock: a silent process makes the supervisor hold
  int max_recoveries = 10;              // contingencies handled before the run fails
  double recovery_timeout_s = 3.0;
  double stop_after_s = 0.5;            // after the last task (or a failure): stop the simulator
  int status_every_ticks = 10;          // DMPL_SUPERVISOR_STATUS rate (and on every change)

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(required_processes));
    a->Visit(DMPL_NVP(heartbeat_timeout_s));
    a->Visit(DMPL_NVP(max_recoveries));
    a->Visit(DMPL_NVP(recovery_timeout_s));
    a->Visit(DMPL_NVP(stop_after_s));
    a->Visit(DMPL_NVP(status_every_ticks));
  }
};

}  // namespace dmpl
