#include "sim_process/noise/noise_injector.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "components/runtime/lcm_eigen.h"
#include "components/runtime/random.h"

namespace dmpl {
namespace {

// Stream ids: one per channel, so adding noise to one channel never shifts another's draws.
enum Stream : uint64_t { kJoints = 1, kObject = 2, kTactile = 3 };

bool AllFinite(const double* v, size_t n) {
  return std::all_of(v, v + n, [](double x) { return std::isfinite(x); });
}

template <typename Vec>
bool AllFinite(const Vec& v) {
  return AllFinite(v.data(), v.size());
}

}  // namespace

bool IsFinite(const joint_state_t& m, std::string* why) {
  const size_t n = static_cast<size_t>(std::max<int16_t>(m.num_joints, 0));
  if (m.num_joints < 0 || m.name.size() != n || m.position.size() != n ||
      m.velocity.size() != n || m.effort.size() != n) {
    *why = "joint state with inconsistent sizes";
    return false;
  }
  if (!AllFinite(m.position) || !AllFinite(m.velocity) || !AllFinite(m.effort)) {
    *why = "joint state with NaN/Inf";
    return false;
  }
  return true;
}

bool IsFinite(const object_pose_t& m, std::string* why) {
  if (!AllFinite(m.position, 3) || !AllFinite(m.orientation, 4) ||
      !AllFinite(m.linear_velocity, 3) || !AllFinite(m.angular_velocity, 3)) {
    *why = "object pose with NaN/Inf";
    return false;
  }
  const double norm = std::sqrt(m.orientation[0] * m.orientation[0] +
                                m.orientation[1] * m.orientation[1] +
                                m.orientation[2] * m.orientation[2] +
                                m.orientation[3] * m.orientation[3]);
  if (std::abs(norm - 1.0) > 1e-3) {
    *why = "object pose with a non-unit quaternion";
    return false;
  }
  return true;
}

bool IsFinite(const tactile_t& m, std::string* why) {
  if (m.num_fingers < 0 || m.fingers.size() != static_cast<size_t>(m.num_fingers)) {
    *why = "tactile message with inconsistent sizes";
    return false;
  }
  for (const auto& f : m.fingers) {
    if (!AllFinite(f.position, 3) || !AllFinite(f.normal, 3) || !std::isfinite(f.force_n)) {
      *why = "tactile reading of finger '" + f.finger + "' with NaN/Inf";
      return false;
    }
  }
  return true;
}

NoiseInjector::NoiseInjector(const NoiseParams& params, int64_t seed)
    : params_(params), seed_(seed) {}

void NoiseInjector::Reject(const std::string& why) {
  ++rejected_;
  last_rejection_ = why;
}

template <typename Msg>
const Msg& NoiseInjector::Delayed(Channel<Msg>* channel, const Msg& truth) {
  channel->history.push_back(truth);
  while (channel->history.size() > static_cast<size_t>(params_.delay_ticks) + 1) {
    channel->history.pop_front();
  }
  return channel->history.front();  // truth(k - delay), or the oldest we have
}

std::optional<joint_state_t> NoiseInjector::Sense(const joint_state_t& truth) {
  std::string why;
  if (!IsFinite(truth, &why)) {
    Reject(why);
    return std::nullopt;
  }
  Rng rng(seed_, truth.seq, kJoints);
  joint_state_t out = Delayed(&joints_, truth);
  if (params_.dropout_probability > 0 && rng.Uniform() < params_.dropout_probability &&
      joints_.last_sent) {
    ++dropped_;
    out = *joints_.last_sent;  // the reading is lost: the driver repeats the previous one
  } else {
    for (auto& q : out.position) q += params_.joint_position_sigma * rng.Normal();
    for (auto& qd : out.velocity) qd += params_.joint_velocity_sigma * rng.Normal();
  }
  out.seq = truth.seq;
  out.utime = truth.utime;
  joints_.last_sent = out;
  return out;
}

std::optional<object_pose_t> NoiseInjector::Sense(const object_pose_t& truth) {
  std::string why;
  if (!IsFinite(truth, &why)) {
    Reject(why);
    return std::nullopt;
  }
  Rng rng(seed_, truth.seq, kObject);
  object_pose_t out = Delayed(&object_, truth);
  if (params_.dropout_probability > 0 && rng.Uniform() < params_.dropout_probability) {
    ++dropped_;
    if (object_.last_sent) out = *object_.last_sent;
    out.valid = false;  // vision lost the object this tick
  } else {
    for (double& p : out.position) p += params_.object_position_sigma * rng.Normal();
    if (params_.object_orientation_sigma > 0) {
      const Eigen::Vector3d rv(rng.Normal(), rng.Normal(), rng.Normal());
      const Eigen::Vector3d w = params_.object_orientation_sigma * rv;
      const Eigen::Quaterniond dq(Eigen::AngleAxisd(w.norm(), w.normalized()));
      ToArray(Eigen::Quaterniond(dq * ToQuaternion(out.orientation)).normalized(),
              out.orientation);
    }
  }
  // A pose sensor does not measure the twist.
  std::fill(out.linear_velocity, out.linear_velocity + 3, 0.0);
  std::fill(out.angular_velocity, out.angular_velocity + 3, 0.0);
  out.seq = truth.seq;
  out.utime = truth.utime;
  object_.last_sent = out;
  return out;
}

std::optional<tactile_t> NoiseInjector::Sense(const tactile_t& truth) {
  std::string why;
  if (!IsFinite(truth, &why)) {
    Reject(why);
    return std::nullopt;
  }
  Rng rng(seed_, truth.seq, kTactile);
  tactile_t out = Delayed(&tactile_, truth);
  if (params_.dropout_probability > 0 && rng.Uniform() < params_.dropout_probability &&
      tactile_.last_sent) {
    ++dropped_;
    out = *tactile_.last_sent;
  } else {
    for (auto& f : out.fingers) {
      // Draw for every finger, in contact or not, so one finger's contact does not shift
      // another's noise.
      const double n[4] = {rng.Normal(), rng.Normal(), rng.Normal(), rng.Normal()};
      if (!f.in_contact) continue;
      for (int i = 0; i < 3; ++i) {
        f.position[i] += params_.contact_position_offset[i] + params_.contact_position_sigma * n[i];
      }
      f.force_n = std::max(
          0.0, params_.force_scale * f.force_n + params_.force_bias + params_.force_sigma * n[3]);
    }
  }
  out.seq = truth.seq;
  out.utime = truth.utime;
  tactile_.last_sent = out;
  return out;
}

std::optional<hand_sensors_t> NoiseInjector::Sense(const hand_sensors_t& truth) {
  if (truth.joints.seq != truth.seq || truth.object.seq != truth.seq ||
      truth.tactile.seq != truth.seq) {
    Reject("sensors of tick " + std::to_string(truth.seq) + " with parts of other ticks");
    return std::nullopt;
  }
  auto joints = Sense(truth.joints);
  auto object = Sense(truth.object);
  auto tactile = Sense(truth.tactile);
  if (!joints || !object || !tactile) return std::nullopt;
  hand_sensors_t out{};
  out.run_id = truth.run_id;
  out.utime = truth.utime;
  out.seq = truth.seq;
  out.joints = std::move(*joints);
  out.object = *object;
  out.tactile = std::move(*tactile);
  return out;
}

}  // namespace dmpl
