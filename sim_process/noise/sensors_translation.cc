#include "sim_process/noise/sensors_translation.h"

#include <algorithm>

namespace dmpl {
namespace {

template <size_t N>
std::array<double, N> ToStdArray(const double (&a)[N]) {
  std::array<double, N> out;
  std::copy(a, a + N, out.begin());
  return out;
}

template <size_t N>
void Copy(const std::array<double, N>& from, double (&to)[N]) {
  std::copy(from.begin(), from.end(), to);
}

}  // namespace

std::optional<HandReading> ToReading(const hand_sensors_t& m, std::string* why) {
  if (m.joints.seq != m.seq || m.object.seq != m.seq || m.tactile.seq != m.seq) {
    *why = "sensors of tick " + std::to_string(m.seq) + " with parts of other ticks";
    return std::nullopt;
  }
  // The messages' count fields (the arrays' agreement with each other is the core's check).
  if (m.joints.num_joints < 0 || static_cast<size_t>(m.joints.num_joints) != m.joints.name.size()) {
    *why = "joint state with inconsistent sizes";
    return std::nullopt;
  }
  if (m.tactile.num_fingers < 0 ||
      m.tactile.fingers.size() != static_cast<size_t>(m.tactile.num_fingers)) {
    *why = "tactile message with inconsistent sizes";
    return std::nullopt;
  }
  HandReading r;
  r.seq = m.seq;
  r.utime = m.utime;
  r.joints = {m.joints.name, m.joints.position, m.joints.velocity, m.joints.effort};
  r.object.valid = m.object.valid;
  r.object.position = ToStdArray(m.object.position);
  r.object.orientation = ToStdArray(m.object.orientation);
  r.object.linear_velocity = ToStdArray(m.object.linear_velocity);
  r.object.angular_velocity = ToStdArray(m.object.angular_velocity);
  for (const fingertip_contact_t& f : m.tactile.fingers) {
    r.tips.push_back({f.finger, f.in_contact != 0, ToStdArray(f.position), ToStdArray(f.normal),
                      f.force_n, f.num_points});
  }
  r.gravity = ToStdArray(m.gravity);
  return r;
}

hand_sensors_t ToMessage(const HandReading& r) {
  hand_sensors_t m{};
  m.utime = r.utime;
  m.seq = r.seq;
  joint_state_t& j = m.joints;
  j.utime = r.utime;
  j.seq = r.seq;
  j.num_joints = static_cast<int16_t>(r.joints.names.size());
  j.name = r.joints.names;
  j.position = r.joints.position;
  j.velocity = r.joints.velocity;
  j.effort = r.joints.effort;
  object_pose_t& o = m.object;
  o.utime = r.utime;
  o.seq = r.seq;
  o.valid = r.object.valid;
  Copy(r.object.position, o.position);
  Copy(r.object.orientation, o.orientation);
  Copy(r.object.linear_velocity, o.linear_velocity);
  Copy(r.object.angular_velocity, o.angular_velocity);
  tactile_t& t = m.tactile;
  t.utime = r.utime;
  t.seq = r.seq;
  t.num_fingers = static_cast<int8_t>(r.tips.size());
  for (const TipReading& tip : r.tips) {
    fingertip_contact_t f{};
    f.finger = tip.finger;
    f.in_contact = tip.in_contact;
    Copy(tip.position, f.position);
    Copy(tip.normal, f.normal);
    f.force_n = tip.force_n;
    f.num_points = static_cast<int16_t>(tip.num_points);
    t.fingers.push_back(f);
  }
  Copy(r.gravity, m.gravity);
  return m;
}

}  // namespace dmpl
