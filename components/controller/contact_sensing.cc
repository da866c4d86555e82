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

LinkContact FindLinkContact(const HandKinematics& kin, int f,
                            const std::vector<double>& q, const std::vector<double>& effort,
                            double tip_force_n, const Eigen::Vector3d& normal,
                            double threshold_nm) {
  const std::vector<int>& joints = kin.joint_indices(f);
  Eigen::Vector3d tip;
  Eigen::Matrix3Xd jac;
  kin.finger(f).TipJacobian(kin.FingerJoints(f, q), &tip, &jac);
  // In equilibrium the servos' torques balance the contact forces: effort + J^T f = 0 for a
  // contact on the tip only.
  const Eigen::VectorXd explained = jac.transpose() * (tip_force_n * normal);
  LinkContact contact;
  for (int j = static_cast<int>(joints.size()) - 1; j >= 0; --j) {
    const double residual = effort[joints[j]] + explained[j];
    if (std::abs(residual) <= threshold_nm) continue;
    contact.joint = j;
    contact.torque_nm = residual;
    contact.link = kin.finger(f).LinkAfterJoint(j);
    break;
  }
  return contact;
}

}  // namespace dmpl
