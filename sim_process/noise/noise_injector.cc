#include "sim_process/noise/noise_injector.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "components/runtime/random.h"

namespace dmpl {
namespace {

// Stream ids: one per channel, so adding noise to one channel never shifts another's draws.
enum Stream : uint64_t { kJoints = 1, kObject = 2, kTactile = 3, kGravity = 4 };

template <typename Values>
bool AllFinite(const Values& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace

bool IsValid(const JointsReading& r, std::string* why) {
  const size_t n = r.names.size();
  if (r.position.size() != n || r.velocity.size() != n || r.effort.size() != n) {
    *why = "joint state with inconsistent sizes";
    return false;
  }
  if (!AllFinite(r.position) || !AllFinite(r.velocity) || !AllFinite(r.effort)) {
    *why = "joint state with NaN/Inf";
    return false;
  }
  return true;
}

bool IsValid(const ObjectPoseReading& r, std::string* why) {
  if (!AllFinite(r.position) || !AllFinite(r.orientation) || !AllFinite(r.linear_velocity) ||
      !AllFinite(r.angular_velocity)) {
    *why = "object pose with NaN/Inf";
    return false;
  }
  const auto& q = r.orientation;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-3) {
    *why = "object pose with a non-unit quaternion";
    return false;
  }
  return true;
}

bool IsValid(const std::vector<TipReading>& r, std::string* why) {
  for (const TipReading& f : r) {
    if (!AllFinite(f.position) || !AllFinite(f.normal) || !std::isfinite(f.force_n)) {
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

std::optional<JointsReading> NoiseInjector::Sense(int64_t seq, const JointsReading& truth) {
  std::string why;
  if (!IsValid(truth, &why)) {
    Reject(why);
    return std::nullopt;
  }
  Rng rng(seed_, seq, kJoints);
  JointsReading out = Delayed(&joints_, truth);
  if (params_.dropout_probability > 0 && rng.Uniform() < params_.dropout_probability &&
      joints_.last_sent) {
    ++dropped_;
    out = *joints_.last_sent;  // the reading is lost: the driver repeats the previous one
  } else {
    for (auto& q : out.position) q += params_.joint_position_sigma * rng.Normal();
    for (auto& qd : out.velocity) qd += params_.joint_velocity_sigma * rng.Normal();
  }
  joints_.last_sent = out;
  return out;
}

std::optional<ObjectPoseReading> NoiseInjector::Sense(int64_t seq,
                                                      const ObjectPoseReading& truth) {
  std::string why;
  if (!IsValid(truth, &why)) {
    Reject(why);
    return std::nullopt;
  }
  Rng rng(seed_, seq, kObject);
  ObjectPoseReading out = Delayed(&object_, truth);
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
      const auto& q = out.orientation;
      const Eigen::Quaterniond noisy =
          Eigen::Quaterniond(dq * Eigen::Quaterniond(q[0], q[1], q[2], q[3])).normalized();
      out.orientation = {noisy.w(), noisy.x(), noisy.y(), noisy.z()};
    }
  }
  // A pose sensor does not measure the twist.
  out.linear_velocity = {0.0, 0.0, 0.0};
  out.angular_velocity = {0.0, 0.0, 0.0};
  object_.last_sent = out;
  return out;
}

std::optional<std::vector<TipReading>> NoiseInjector::Sense(
    int64_t seq, const std::vector<TipReading>& truth) {
  std::string why;
  if (!IsValid(truth, &why)) {
    Reject(why);
    return std::nullopt;
  }
  Rng rng(seed_, seq, kTactile);
  std::vector<TipReading> out = Delayed(&tactile_, truth);
  if (params_.dropout_probability > 0 && rng.Uniform() < params_.dropout_probability &&
      tactile_.last_sent) {
    ++dropped_;
    out = *tactile_.last_sent;
  } else {
    for (TipReading& f : out) {
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
  tactile_.last_sent = out;
  return out;
}

std::optional<std::array<double, 3>> NoiseInjector::SenseGravity(
    int64_t seq, const std::array<double, 3>& truth) {
  if (!AllFinite(truth)) {
    Reject("gravity with NaN/Inf");
    return std::nullopt;
  }
  if (params_.gravity_direction_sigma <= 0) return truth;
  Rng rng(seed_, seq, kGravity);
  const Eigen::Vector3d w = params_.gravity_direction_sigma *
                            Eigen::Vector3d(rng.Normal(), rng.Normal(), rng.Normal());
  const Eigen::Vector3d g =
      Eigen::AngleAxisd(w.norm(), w.normalized()) * Eigen::Vector3d(truth[0], truth[1], truth[2]);
  return std::array<double, 3>{g[0], g[1], g[2]};
}

std::optional<HandReading> NoiseInjector::Sense(const HandReading& truth) {
  auto joints = Sense(truth.seq, truth.joints);
  auto object = Sense(truth.seq, truth.object);
  auto tips = Sense(truth.seq, truth.tips);
  auto gravity = SenseGravity(truth.seq, truth.gravity);
  if (!joints || !object || !tips || !gravity) return std::nullopt;
  HandReading out;
  out.seq = truth.seq;
  out.utime = truth.utime;
  out.joints = std::move(*joints);
  out.object = *object;
  out.tips = std::move(*tips);
  out.gravity = *gravity;
  return out;
}

}  // namespace dmpl
