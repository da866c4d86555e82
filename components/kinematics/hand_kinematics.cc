#include "components/kinematics/hand_kinematics.h"

#include <sstream>

#include <kdl/tree.hpp>

#include "components/kinematics/urdf_to_kdl.h"
#include "components/runtime/check.h"

namespace dmpl {

FingerKinematics::FingerKinematics(std::string name, const KDL::Chain& chain,
                                   Eigen::VectorXd lower, Eigen::VectorXd upper)
    : name_(std::move(name)),
      chain_(std::make_unique<KDL::Chain>(chain)),
      lower_(std::move(lower)),
      upper_(std::move(upper)),
      fk_(std::make_unique<KDL::ChainFkSolverPos_recursive>(*chain_)),
      jac_(std::make_unique<KDL::ChainJntToJacSolver>(*chain_)),
      q_kdl_(chain_->getNrOfJoints()),
      jac_kdl_(chain_->getNrOfJoints()) {
  DMPL_DEMAND(static_cast<int>(chain_->getNrOfJoints()) == lower_.size());
  for (int axis = 0; axis < 3; ++axis) {
    KDL::Vector unit = KDL::Vector::Zero();
    unit(axis) = 1.0;
    unit_gravity_[axis] = std::make_unique<KDL::ChainDynParam>(*chain_, unit);
  }
  for (const KDL::Segment& segment : chain_->segments) {
    if (segment.getJoint().getType() != KDL::Joint::None) {
      links_after_joints_.push_back(segment.getName());
    }
  }
}

Eigen::Vector3d FingerKinematics::TipPosition(const Eigen::VectorXd& q) const {
  q_kdl_.data = q;
  KDL::Frame frame;
  DMPL_DEMAND(fk_->JntToCart(q_kdl_, frame) >= 0);
  return Eigen::Vector3d(frame.p.x(), frame.p.y(), frame.p.z());
}

void FingerKinematics::PositionJacobian(const Eigen::VectorXd& q, Eigen::Matrix3Xd* jac) const {
  q_kdl_.data = q;
  // KDL's Jacobian is referenced to the chain's tip: its linear rows are the tip velocity.
  DMPL_DEMAND(jac_->JntToJac(q_kdl_, jac_kdl_) >= 0);
  *jac = jac_kdl_.data.topRows<3>();
}

Eigen::VectorXd FingerKinematics::GravityTorques(const Eigen::VectorXd& q,
                                                 const Eigen::Vector3d& gravity) const {
  q_kdl_.data = q;
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(q.size());
  KDL::JntArray unit_tau(chain_->getNrOfJoints());
  for (int axis = 0; axis < 3; ++axis) {
    if (gravity[axis] == 0.0) continue;
    DMPL_DEMAND(unit_gravity_[axis]->JntToGravity(q_kdl_, unit_tau) >= 0);
    tau += gravity[axis] * unit_tau.data;
  }
  return tau;
}

void FingerKinematics::PointJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& offset,
                                     Eigen::Matrix3Xd* jac) const {
  q_kdl_.data = q;
  DMPL_DEMAND(jac_->JntToJac(q_kdl_, jac_kdl_) >= 0);
  // v + w x r, with w x r = -r x w.
  Eigen::Matrix3d cross_offset;
  cross_offset << 0, -offset.z(), offset.y(), offset.z(), 0, -offset.x(), -offset.y(), offset.x(),
      0;
  *jac = jac_kdl_.data.topRows<3>() - cross_offset * jac_kdl_.data.bottomRows<3>();
}

void FingerKinematics::TipFrame(const Eigen::VectorXd& q, Eigen::Vector3d* tip,
                                 Eigen::Vector3d* axis) const {
  q_kdl_.data = q;
  KDL::Frame frame;
  DMPL_DEMAND(fk_->JntToCart(q_kdl_, frame) >= 0);
  *tip = Eigen::Vector3d(frame.p.x(), frame.p.y(), frame.p.z());
  const KDL::Vector z = frame.M.UnitZ();
  *axis = Eigen::Vector3d(z.x(), z.y(), z.z());
}

void FingerKinematics::TipAxis(const Eigen::VectorXd& q, Eigen::Vector3d* axis,
                                Eigen::Matrix3Xd* omega) const {
  Eigen::Vector3d tip;
  TipFrame(q, &tip, axis);  // sets q_kdl_ for the Jacobian too
  // KDL's Jacobian: its angular rows are the joints' axes in the base frame.
  DMPL_DEMAND(jac_->JntToJac(q_kdl_, jac_kdl_) >= 0);
  *omega = jac_kdl_.data.bottomRows<3>();
}

void FingerKinematics::LinkFrames(const Eigen::VectorXd& q,
                                  std::vector<Eigen::Isometry3d>* frames) const {
  DMPL_DEMAND(q.size() == num_joints());
  frames->resize(num_links());
  KDL::Frame frame = KDL::Frame::Identity();
  int j = 0;
  for (int k = 0; k < num_links(); ++k) {
    const KDL::Segment& segment = chain_->getSegment(k);
    const bool moves = segment.getJoint().getType() != KDL::Joint::None;
    frame = frame * segment.pose(moves ? q[j++] : 0.0);
    Eigen::Isometry3d& out = (*frames)[k];
    out.setIdentity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out.linear()(r, c) = frame.M(r, c);
      out.translation()[r] = frame.p[r];
    }
  }
}

HandKinematics::HandKinematics(const HandModel& model) {
  const KDL::Tree tree = UrdfToKdlTree(model);
  const std::string& root = model.links()[0].name;
  for (const FingerInfo& f : model.fingers()) {
    KDL::Chain chain;
    DMPL_DEMAND(tree.getChain(root, model.links()[f.tip_link].name, chain));
    const int n = static_cast<int>(f.joints.size());
    Eigen::VectorXd lower(n), upper(n);
    for (int k = 0; k < n; ++k) {
      lower[k] = model.actuated_joint(f.joints[k]).lower;
      upper[k] = model.actuated_joint(f.joints[k]).upper;
    }
    fingers_.emplace_back(f.name, chain, lower, upper);
    joint_indices_.push_back(f.joints);
  }
  num_joints_ = model.num_actuated();
}

Eigen::VectorXd HandKinematics::FingerJoints(int f, const std::vector<double>& q) const {
  const auto& idx = joint_indices_[f];
  Eigen::VectorXd out(idx.size());
  for (size_t k = 0; k < idx.size(); ++k) out[k] = q[idx[k]];
  return out;
}

Eigen::Vector3d HandKinematics::TipPosition(int f, const std::vector<double>& q) const {
  return fingers_[f].TipPosition(FingerJoints(f, q));
}

std::string HandKinematics::OutOfLimits(const std::vector<double>& q, double margin_rad) const {
  for (int f = 0; f < num_fingers(); ++f) {
    const FingerKinematics& finger = fingers_[f];
    for (int j = 0; j < finger.num_joints(); ++j) {
      const double v = q[joint_indices_[f][j]];
      if (v < finger.lower()[j] - margin_rad || v > finger.upper()[j] + margin_rad) {
        std::ostringstream os;  // %g: an absurd value stays one short number
        os << finger.name() << " joint " << j << " at " << v << " rad, outside ["
           << finger.lower()[j] << ", " << finger.upper()[j] << "]";
        return os.str();
      }
    }
  }
  return "";
}

int HandKinematics::FindFinger(const std::string& name) const {
  for (int f = 0; f < num_fingers(); ++f) {
    if (fingers_[f].name() == name) return f;
  }
  return -1;
}

}  // namespace dmpl
