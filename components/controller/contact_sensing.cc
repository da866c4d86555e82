#include "components/controller/contact_sensing.h"

#include <cmath>

namespace dmpl {

ContactNormal NormalFromTip(const Eigen::Vector3d& tip_centre, const Eigen::Vector3d& contact,
                            double tip_radius) {
  ContactNormal c;
  const Eigen::Vector3d inward = tip_centre - contact;
  const double distance = inward.norm();
  c.off_surface_m = distance - tip_radius;
  if (distance > 1e-9) c.normal = inward / distance;
  return c;
}

namespace {

Eigen::Matrix<double, 3, 2> TangentBasis(const Eigen::Vector3d& unit_normal) {
  Eigen::Matrix<double, 3, 2> tangent;
  tangent.col(0) = unit_normal.unitOrthogonal();
  tangent.col(1) = unit_normal.cross(tangent.col(0));
  return tangent;
}

// Finger f's part of the servos' efforts (`effort` is the hand's joint vector).
Eigen::VectorXd FingerEfforts(const HandKinematics& kin, int f, const std::vector<double>& effort) {
  const std::vector<int>& joints = kin.joint_indices(f);
  Eigen::VectorXd tau(static_cast<Eigen::Index>(joints.size()));
  for (size_t j = 0; j < joints.size(); ++j) tau[static_cast<Eigen::Index>(j)] = effort[joints[j]];
  return tau;
}

// Whether a tangential tip force within `friction` times the normal force `tip_force_n` leaves
// every joint of `residual` within `threshold_nm`: the least-squares tangential force (two
// unknowns, one equation per joint), pulled back onto the friction cone if it lies beyond.
bool FrictionExplains(const Eigen::Matrix3Xd& jac, const Eigen::Vector3d& normal,
                      const Eigen::VectorXd& residual, double tip_force_n, double friction,
                      double threshold_nm) {
  if (friction <= 0 || tip_force_n <= 0 || normal.norm() < 0.5) return false;
  const Eigen::Matrix<double, 3, 2> tangent = TangentBasis(normal.normalized());
  const Eigen::MatrixX2d effect = jac.transpose() * tangent;  // joint torque per tangential N
  Eigen::Vector2d force = -effect.colPivHouseholderQr().solve(residual);
  const double most = friction * tip_force_n;
  if (force.norm() > most) force *= most / force.norm();
  return (residual + effect * force).cwiseAbs().maxCoeff() <= threshold_nm;
}

}  // namespace

Eigen::Vector3d TipTangentialForce(const HandKinematics& kin, int f, const std::vector<double>& q,
                                   const std::vector<double>& effort, double tip_force_n,
                                   const Eigen::Vector3d& contact, const Eigen::Vector3d& gravity) {
  const Eigen::VectorXd finger_q = kin.FingerJoints(f, q);
  const Eigen::Vector3d centre = kin.finger(f).TipPosition(finger_q);
  const Eigen::Vector3d normal = NormalFromTip(centre, contact, 0.0).normal;
  if (tip_force_n <= 0 || normal.isZero()) return Eigen::Vector3d::Zero();
  Eigen::Matrix3Xd jac;
  kin.finger(f).PointJacobian(finger_q, contact - centre, &jac);
  const Eigen::VectorXd residual = jac.transpose() * (tip_force_n * normal) +
                                   FingerEfforts(kin, f, effort) -
                                   kin.finger(f).GravityTorques(finger_q, gravity);
  const Eigen::Matrix<double, 3, 2> tangent = TangentBasis(normal);
  const Eigen::MatrixX2d effect = jac.transpose() * tangent;
  return tangent * (-effect.colPivHouseholderQr().solve(residual));
}

LinkContact FindLinkContact(const HandKinematics& kin, int f,
                            const std::vector<double>& q, const std::vector<double>& effort,
                            double tip_force_n, const Eigen::Vector3d& normal,
                            double threshold_nm, double friction) {
  // In equilibrium the servos' torques balance the contact forces: effort + J^T f = 0 for a
  // contact on the tip only. A tip that feels nothing leaves the efforts alone (no Jacobian).
  const bool pressed = tip_force_n != 0.0;
  Eigen::Matrix3Xd jac;
  Eigen::VectorXd residual = FingerEfforts(kin, f, effort);
  if (pressed) {
    kin.finger(f).PositionJacobian(kin.FingerJoints(f, q), &jac);
    residual += jac.transpose() * (tip_force_n * normal);
  }
  LinkContact contact;
  if (residual.cwiseAbs().maxCoeff() <= threshold_nm ||
      (pressed &&
       FrictionExplains(jac, normal, residual, tip_force_n, friction, threshold_nm))) {
    return contact;
  }
  // The link: the outermost joint the residual (without friction) is above the threshold at.
  for (int j = static_cast<int>(residual.size()) - 1; j >= 0; --j) {
    if (std::abs(residual[j]) <= threshold_nm) continue;
    contact.joint = j;
    contact.torque_nm = residual[j];
    contact.link = kin.finger(f).LinkAfterJoint(j);
    break;
  }
  return contact;
}

}  // namespace dmpl
