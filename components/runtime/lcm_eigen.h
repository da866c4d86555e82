#pragma once
// Eigen <-> the fixed arrays of dmpl's LCM messages: positions [x, y, z] and orientations
// [w, x, y, z], in the palm frame. Written once, used by every node that translates a message.
#include <Eigen/Geometry>

namespace dmpl {

inline Eigen::Vector3d ToVector3(const double (&a)[3]) { return {a[0], a[1], a[2]}; }

inline void ToArray(const Eigen::Vector3d& v, double (&a)[3]) {
  a[0] = v.x();
  a[1] = v.y();
  a[2] = v.z();
}

// As sent: not normalised (a reader that needs a rotation normalises, after its checks).
inline Eigen::Quaterniond ToQuaternion(const double (&a)[4]) {
  return Eigen::Quaterniond(a[0], a[1], a[2], a[3]);
}

inline void ToArray(const Eigen::Quaterniond& q, double (&a)[4]) {
  a[0] = q.w();
  a[1] = q.x();
  a[2] = q.y();
  a[3] = q.z();
}

// A pose from a message's position and orientation, the orientation normalised.
inline Eigen::Isometry3d ToPose(const double (&p)[3], const double (&q)[4]) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = ToVector3(p);
  t.linear() = ToQuaternion(q).normalized().toRotationMatrix();
  return t;
}

}  // namespace dmpl
