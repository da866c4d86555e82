#include "components/ik/hand_ik.h"

#include <algorithm>
#include <cmath>

#include "components/runtime/check.h"

namespace dmpl {

HandIk::HandIk(const HandKinematics& kinematics, const IkParams& params)
    : kin_(kinematics), params_(params), reports_(kinematics.num_fingers()) {}

const std::vector<double>& HandIk::Step(
    const std::vector<double>& measured,
    const std::vector<std::optional<Eigen::Vector3d>>& targets,
    const std::vector<Eigen::Vector3d>& approaches) {
  DMPL_DEMAND(static_cast<int>(measured.size()) == kin_.num_joints());
  DMPL_DEMAND(static_cast<int>(targets.size()) == kin_.num_fingers());
  DMPL_DEMAND(approaches.empty() || approaches.size() == targets.size());
  if (command_.empty()) {
    // First tick: start where the hand is (clamped into the limits).
    command_ = measured;
    for (int f = 0; f < kin_.num_fingers(); ++f) {
      const auto& idx = kin_.joint_indices(f);
      for (size_t k = 0; k < idx.size(); ++k) {
        command_[idx[k]] = std::clamp(command_[idx[k]], kin_.finger(f).lower()[k],
                                      kin_.finger(f).upper()[k]);
      }
    }
  }
  for (int f = 0; f < kin_.num_fingers(); ++f) {
    FingerIkReport& report = reports_[f];
    if (!targets[f]) {
      report = {IkStatus::kHolding, 0.0, 0};
      continue;
    }
    if (!targets[f]->allFinite()) {
      report = {IkStatus::kRejected, 0.0, 0};
      continue;
    }
    const FingerKinematics& finger = kin_.finger(f);
    const Eigen::VectorXd seed = kin_.FingerJoints(f, command_);
    const Eigen::Vector3d approach =
        approaches.empty() || !approaches[f].allFinite() ? Eigen::Vector3d::Zero()
                                                         : approaches[f];
    const IkResult r = SolveFingerIk(finger, seed, *targets[f], params_, approach);
    report = {r.status, r.residual_m, r.iterations};
    const auto& idx = kin_.joint_indices(f);
    for (size_t k = 0; k < idx.size(); ++k) {
      const double step = std::clamp(r.q[k] - seed[k], -params_.max_joint_step_rad,
                                     params_.max_joint_step_rad);
      command_[idx[k]] = std::clamp(seed[k] + step, finger.lower()[k], finger.upper()[k]);
    }
  }
  return command_;
}

}  // namespace dmpl
