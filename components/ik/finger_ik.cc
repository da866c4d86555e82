#include "components/ik/finger_ik.h"

#include <Eigen/Cholesky>

namespace dmpl {

namespace {

IkResult SolveFrom(const FingerKinematics& finger, const Eigen::VectorXd& seed,
                   const Eigen::Vector3d& target, const IkParams& params) {
  const Eigen::VectorXd& lo = finger.lower();
  const Eigen::VectorXd& hi = finger.upper();
  const int n = finger.num_joints();
  const Eigen::VectorXd mid = (lo + hi) / 2.0;
  IkResult r;
  r.q = seed.cwiseMax(lo).cwiseMin(hi);
  Eigen::Vector3d tip;
  Eigen::Matrix3Xd jac(3, n);
  const double lambda2 = params.damping_m * params.damping_m;
  for (r.iterations = 0; r.iterations < params.max_iterations; ++r.iterations) {
    finger.TipJacobian(r.q, &tip, &jac);
    const Eigen::Vector3d e = target - tip;
    r.residual_m = e.norm();
    if (r.residual_m < params.tolerance_m) break;
    Eigen::VectorXd dq;
    Eigen::VectorXi active = Eigen::VectorXi::Ones(n);
    // Two passes: solve, then freeze joints the step pushes through a limit, and solve again.
    for (int pass = 0; pass < 2; ++pass) {
      Eigen::Matrix3Xd ja = jac;
      for (int k = 0; k < n; ++k) {
        if (!active[k]) ja.col(k).setZero();
      }
      const Eigen::Matrix3d a = ja * ja.transpose() + lambda2 * Eigen::Matrix3d::Identity();
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(a);
      dq = ja.transpose() * ldlt.solve(e);
      // Null space of the position task: drift the redundancy toward mid-range.
      Eigen::VectorXd pull = params.nullspace_gain * (mid - r.q);
      for (int k = 0; k < n; ++k) {
        if (!active[k]) pull[k] = 0.0;
      }
      dq += pull - ja.transpose() * ldlt.solve(ja * pull);
      bool changed = false;
      for (int k = 0; k < n; ++k) {
        if (active[k] && ((r.q[k] <= lo[k] && dq[k] < 0) || (r.q[k] >= hi[k] && dq[k] > 0))) {
          active[k] = 0;
          changed = true;
        }
      }
      if (!changed) break;
    }
    r.q = (r.q + dq).cwiseMax(lo).cwiseMin(hi);
  }
  finger.TipJacobian(r.q, &tip, &jac);
  r.residual_m = (target - tip).norm();
  const bool at_limit = ((r.q - lo).array() < 1e-9).any() || ((hi - r.q).array() < 1e-9).any();
  if (r.residual_m < params.tolerance_m) {
    r.status = at_limit ? IkStatus::kAtLimit : IkStatus::kConverged;
  } else {
    r.status = IkStatus::kUnreachable;
  }
  return r;
}

}  // namespace

IkResult SolveFingerIk(const FingerKinematics& finger, const Eigen::VectorXd& seed,
                       const Eigen::Vector3d& target, const IkParams& params) {
  IkResult best = SolveFrom(finger, seed, target, params);
  // Limits can trap the local solver; try seeds between the first answer and mid-range.
  const Eigen::VectorXd mid = (finger.lower() + finger.upper()) / 2.0;
  for (int i = 1; i <= params.restarts && best.status == IkStatus::kUnreachable; ++i) {
    const double w = static_cast<double>(i) / params.restarts;
    IkResult r = SolveFrom(finger, (1.0 - w) * seed + w * mid, target, params);
    r.iterations += best.iterations;
    if (r.residual_m < best.residual_m) {
      best = r;
    } else {
      best.iterations = r.iterations;
    }
  }
  return best;
}

}  // namespace dmpl
