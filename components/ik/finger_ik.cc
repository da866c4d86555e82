#include "components/ik/finger_ik.h"

#include <Eigen/Cholesky>

namespace dmpl {

namespace {

// What the redundancy pursues: mid-range, and the tip's axis turned toward `approach` (the
// gradient of axis . approach: joint k turns the axis by omega_k x axis).
Eigen::VectorXd NullSpacePull(const FingerKinematics& finger, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& mid, const IkParams& params,
                              const Eigen::Vector3d& approach) {
  Eigen::VectorXd pull = params.nullspace_gain * (mid - q);
  if (params.approach_gain > 0 && approach.squaredNorm() > 0) {
    Eigen::Vector3d axis;
    Eigen::Matrix3Xd omega;
    finger.TipAxis(q, &axis, &omega);
    pull += params.approach_gain * omega.transpose() * axis.cross(approach);
  }
  return pull;
}

IkResult SolveFrom(const FingerKinematics& finger, const Eigen::VectorXd& seed,
                   const Eigen::Vector3d& target, const IkParams& params,
                   const Eigen::Vector3d& approach) {
  const Eigen::VectorXd& lo = finger.lower();
  const Eigen::VectorXd& hi = finger.upper();
  const int n = finger.num_joints();
  const Eigen::VectorXd mid = (lo + hi) / 2.0;
  IkResult r;
  r.q = seed.cwiseMax(lo).cwiseMin(hi);
  Eigen::Matrix3Xd jac(3, n);
  const double lambda2 = params.damping_m * params.damping_m;
  // The tip is known at r.q until a step moves it; the Jacobian only when a step is taken (a
  // warm-started solve usually converges without one).
  Eigen::Vector3d tip = finger.TipPosition(r.q);
  for (r.iterations = 0; r.iterations < params.max_iterations; ++r.iterations) {
    const Eigen::Vector3d e = target - tip;
    r.residual_m = e.norm();
    // A finger with an approach direction turns its axis a step each tick even while its tip
    // is where it should be.
    const bool turning =
        r.iterations == 0 && params.approach_gain > 0 && approach.squaredNorm() > 0;
    if (r.residual_m < params.tolerance_m && !turning) break;
    finger.PositionJacobian(r.q, &jac);
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
      // Null space of the position task: the redundancy drifts toward what it pursues.
      Eigen::VectorXd pull = NullSpacePull(finger, r.q, mid, params, approach);
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
    tip = finger.TipPosition(r.q);
  }
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
                       const Eigen::Vector3d& target, const IkParams& params,
                       const Eigen::Vector3d& approach) {
  IkResult best = SolveFrom(finger, seed, target, params, approach);
  // Limits can trap the local solver; try seeds between the first answer and mid-range.
  const Eigen::VectorXd mid = (finger.lower() + finger.upper()) / 2.0;
  for (int i = 1; i <= params.restarts && best.status == IkStatus::kUnreachable; ++i) {
    const double w = static_cast<double>(i) / params.restarts;
    IkResult r = SolveFrom(finger, (1.0 - w) * seed + w * mid, target, params, approach);
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
