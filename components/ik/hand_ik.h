#pragma once
// The IK server's core: fingertip targets -> one joint command for the hand, per tick. Warm
// starts from the last command, bounds each joint's change per tick, reports a status per finger,
// and rejects bad input (NaN) by holding the last safe command.
#include <optional>
#include <vector>

#include "components/ik/finger_ik.h"

namespace dmpl {

struct FingerIkReport {
  IkStatus status = IkStatus::kHolding;
  double residual_m = 0.0;
  int iterations = 0;
};

class HandIk {
 public:
  HandIk(const HandKinematics& kinematics, const IkParams& params);

  // `measured`: the sensed joint vector (hand order). `targets[f]`: the tip target of finger f,
  // or nullopt to hold it; `approaches[f]` (if given): the direction its tip's axis should
  // point (zero: none; finger_ik.h). Returns the joint command (always within limits).
  const std::vector<double>& Step(const std::vector<double>& measured,
                                  const std::vector<std::optional<Eigen::Vector3d>>& targets,
                                  const std::vector<Eigen::Vector3d>& approaches = {});

  const std::vector<FingerIkReport>& reports() const { return reports_; }
  const std::vector<double>& command() const { return command_; }
  bool has_command() const { return !command_.empty(); }

 private:
  const HandKinematics& kin_;
  IkParams params_;
  std::vector<double> command_;
  std::vector<FingerIkReport> reports_;
};

}  // namespace dmpl
