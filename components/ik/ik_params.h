#pragma once
#include "components/runtime/params.h"

namespace dmpl {

// Section `ik`.
struct IkParams {
  double tolerance_m = 1e-4;          // converged when the tip is this close to its target
  int max_iterations = 30;            // per finger and tick (warm started from the last command)
  double damping_m = 2e-3;            // DLS damping (lambda, in metres of tip motion)
  double nullspace_gain = 0.02;       // pulls the redundant joint toward mid-range
  double max_joint_step_rad = 0.01;   // per tick: the command never jumps
  int restarts = 2;                   // extra seeds (mid-range) when a solve does not converge
  // Where a target comes with an approach direction (a finger touching: into the object), the
  // redundancy also turns the fingertip's axis toward it, so that the tip touches with its front
  // and not with the side beside its link (0: mid-range only).
  double approach_gain = 0.0;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(tolerance_m), Above(0));
    a->Visit(DMPL_NVP(max_iterations), AtLeast(1));
    a->Visit(DMPL_NVP(damping_m), AtLeast(0));
    a->Visit(DMPL_NVP(nullspace_gain), AtLeast(0));
    a->Visit(DMPL_NVP(max_joint_step_rad), Above(0));
    a->Visit(DMPL_NVP(restarts), AtLeast(0));
    a->Visit(DMPL_NVP(approach_gain), AtLeast(0));
  }
  void Validate(const std::string& source) const { CheckBounds(*this, source, "ik"); }
};

}  // namespace dmpl
