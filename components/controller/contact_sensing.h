#pragma once
// What touch tells of the object's surface, from sensed channels only (joints, fingertip
// contacts): no object model, no simulator.
//  - A fingertip is a sphere: the surface normal at its contact runs from the contact point to
//    the sphere's centre, which forward kinematics of the sensed joints gives.
//  - A finger that touches with a link (not its tip) shows as joint torque that the tip force
//    does not explain: the servos' efforts plus J^T f of the tip force leave a residual on the
//    joints up to that link and none beyond it.
#include <string>

#include <Eigen/Core>

#include "components/kinematics/hand_kinematics.h"

namespace dmpl {

struct ContactNormal {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, from the object into the fingertip
  // |contact - tip centre| - tip radius: how far the sensed point is from the tip's surface (its
  // noise, or a point that is not on this tip).
  double off_surface_m = 0.0;
};

// The normal at a fingertip contact from the tip sphere's centre (forward kinematics) through
// the sensed contact point.
ContactNormal NormalFromTip(const Eigen::Vector3d& tip_centre, const Eigen::Vector3d& contact,
                            double tip_radius);

// The tangential force on finger f's tip at its sensed `contact` point (palm frame,
// perpendicular to the normal NormalFromTip gives there) that, with the sensed normal force,
// best explains the servos' efforts: in equilibrium effort + J^T f = 0 with f the contact's force
// on the tip, whose normal part the tip's sensor reads and whose tangential part (friction) only
// the joints feel. J is the contact point's: a tangential force acts a tip radius off the tip's
// centre. Least squares over the finger's joints (two unknowns, one equation per joint); zero
// for a tip that feels nothing. The servos' efforts hold the links up too: `gravity` (palm
// frame, m/s^2; the palm's IMU) takes out what their gravity compensation adds (a few hundredths
// of a N m, tenths of a N at the tip). Valid while the finger is near rest and touches with its
// tip alone (FindLinkContact).
Eigen::Vector3d TipTangentialForce(const HandKinematics& kin, int f, const std::vector<double>& q,
                                   const std::vector<double>& effort, double tip_force_n,
                                   const Eigen::Vector3d& contact, const Eigen::Vector3d& gravity);

struct LinkContact {
  // The finger's joint (base first) the contact lies beyond; -1: none. A contact on a link
  // leaves no torque on the joints beyond it, but the joints before it may feel little of it
  // (its line of force passes near their axes): the contact is on this joint's link or on one
  // further out.
  int joint = -1;
  std::string link;          // the link after it (URDF name)
  double torque_nm = 0.0;    // the unexplained torque at that joint
};

// Finger f's link contact, if any: the outermost joint whose sensed effort, with what the tip
// force explains (J^T f, f = force * normal on the tip), leaves more than `threshold_nm`. The
// tip's sensor reads the normal force only, and friction at the tip adds a tangential force of
// up to `friction` times it (a grip carrying the object's weight): only a residual that no
// such tangential force explains (within the threshold on every joint) is a link contact.
// `q` and `effort` are the hand's joint vectors (HandKinematics order); `normal` points from the
// object into the fingertip (NormalFromTip). The residual also holds what the servo adds for
// gravity (gravity compensation: a few hundredths of a N m on this hand), which the threshold
// stays well above.
LinkContact FindLinkContact(const HandKinematics& kin, int f,
                            const std::vector<double>& q, const std::vector<double>& effort,
                            double tip_force_n, const Eigen::Vector3d& normal,
                            double threshold_nm, double friction = 0.0);

}  // namespace dmpl
