#pragma once
// Forward kinematics and Jacobians of each finger: a KDL chain from the palm to the fingertip
// centre, with the URDF joint limits beside it. Pure: no LCM, no simulator.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "components/hand/hand_model.h"

namespace dmpl {

class FingerKinematics {
 public:
  FingerKinematics(std::string name, const KDL::Chain& chain, Eigen::VectorXd lower,
                   Eigen::VectorXd upper);
  const std::string& name() const { return name_; }
  int num_joints() const { return static_cast<int>(lower_.size()); }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }

  // Fingertip centre in the palm frame.
  Eigen::Vector3d TipPosition(const Eigen::VectorXd& q) const;
  // Tip position and the fingertip's axis (TipAxis), from one forward kinematics.
  void TipFrame(const Eigen::VectorXd& q, Eigen::Vector3d* tip, Eigen::Vector3d* axis) const;
  // The tip's 3 x n position Jacobian (KDL's Jacobian solver runs its own forward kinematics:
  // callers that need the tip too ask TipPosition only when they use it).
  void PositionJacobian(const Eigen::VectorXd& q, Eigen::Matrix3Xd* jac) const;
  // The 3 x n Jacobian of a point fixed to the fingertip `offset` (palm frame) from its centre,
  // such as its contact point: the centre's velocity plus the tip's rotation times the offset.
  void PointJacobian(const Eigen::VectorXd& q, const Eigen::Vector3d& offset,
                     Eigen::Matrix3Xd* jac) const;
  // The fingertip's axis (the unit z of the tip frame: the distal link's direction, from its
  // joint to the tip centre) in the palm frame, and each joint's rotation axis there (3 x n):
  // the axis turns by omega_k x axis per unit of joint k.
  void TipAxis(const Eigen::VectorXd& q, Eigen::Vector3d* axis, Eigen::Matrix3Xd* omega) const;
  // The joint torques that hold the finger's links still against `gravity` (palm frame, m/s^2),
  // from the URDF's link masses: what a servo with gravity compensation adds to its effort.
  Eigen::VectorXd GravityTorques(const Eigen::VectorXd& q, const Eigen::Vector3d& gravity) const;
  // The link that joint j (0: the base) moves, as the URDF names it.
  const std::string& LinkAfterJoint(int j) const { return links_after_joints_[j]; }
  // Every link of the chain (the palm's child first, the tip last) and its frame in the palm
  // frame at `q`, as KDL's forward kinematics composes them.
  int num_links() const { return static_cast<int>(chain_->getNrOfSegments()); }
  const std::string& LinkName(int k) const { return chain_->getSegment(k).getName(); }
  void LinkFrames(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>* frames) const;

 private:
  std::string name_;
  std::unique_ptr<KDL::Chain> chain_;  // on the heap: KDL's solvers keep a reference to it
  Eigen::VectorXd lower_, upper_;
  std::vector<std::string> links_after_joints_;
  std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk_;
  std::unique_ptr<KDL::ChainJntToJacSolver> jac_;
  // One per palm axis, each under unit gravity along it: the torques are linear in gravity,
  // which the palm's IMU turns at run time while KDL fixes it per solver.
  std::array<std::unique_ptr<KDL::ChainDynParam>, 3> unit_gravity_;
  mutable KDL::JntArray q_kdl_;
  mutable KDL::Jacobian jac_kdl_;
};

// What a sensed or commanded value of this hand can physically be. A value beyond is a corrupt or
// forged message, rejected like NaN.
struct InputBounds {
  static constexpr double kJointMarginRad = 0.2;    // past a limit: noise, overshoot, calibration
  static constexpr double kMaxForceN = 100.0;       // a fingertip sensor's range (grips are ~1 N)
  static constexpr double kWorkspaceRadiusM = 0.5;  // palm frame; the hand spans about 0.2 m
  // A palm IMU's gravity reading (m/s^2) outside these is not one (zero: a sender left it out).
  static constexpr double kMinGravity = 1.0;
  static constexpr double kMaxGravity = 30.0;
};

class HandKinematics {
 public:
  explicit HandKinematics(const HandModel& model);
  int num_fingers() const { return static_cast<int>(fingers_.size()); }
  const FingerKinematics& finger(int f) const { return fingers_[f]; }
  // Indices of finger f's joints in the hand's joint vector.
  const std::vector<int>& joint_indices(int f) const { return joint_indices_[f]; }
  int num_joints() const { return num_joints_; }
  // Finger f's part of the hand joint vector.
  Eigen::VectorXd FingerJoints(int f, const std::vector<double>& q) const;
  Eigen::Vector3d TipPosition(int f, const std::vector<double>& q) const;
  int FindFinger(const std::string& name) const;
  // Empty when every joint of `q` is within its limits widened by `margin_rad`; else which is
  // not (the caller has checked the size).
  std::string OutOfLimits(const std::vector<double>& q, double margin_rad) const;

 private:
  std::vector<FingerKinematics> fingers_;
  std::vector<std::vector<int>> joint_indices_;
  int num_joints_ = 0;
};

}  // namespace dmpl
