#pragma once
// Position IK of one finger: damped least squares on the tip position with joint limits as an
// active set (a joint at a limit that the step pushes further is taken out of the Jacobian), and a
// null-space pull toward mid-range for the redundant degree of freedom. Never returns a joint
// outside its limits.
#include <Eigen/Core>

#include "components/ik/ik_params.h"
#include "components/kinematics/hand_kinematics.h"

namespace dmpl {

enum class IkStatus { kConverged = 0, kAtLimit = 1, kUnreachable = 2, kRejected = 3, kHolding = 4 };

struct IkResult {
  Eigen::VectorXd q;
  IkStatus status = IkStatus::kUnreachable;
  double residual_m = 0.0;
  int iterations = 0;
};

// `approach` (unit, or zero for none): the direction the fingertip's axis should point; the
// redundancy of the position task turns it that way (params.approach_gain).
IkResult SolveFingerIk(const FingerKinematics& finger, const Eigen::VectorXd& seed,
                       const Eigen::Vector3d& target, const IkParams& params,
                       const Eigen::Vector3d& approach = Eigen::Vector3d::Zero());

}  // namespace dmpl
