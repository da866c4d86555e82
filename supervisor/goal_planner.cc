#include "supervisor/goal_planner.h"

#include <cmath>
#include <stdexcept>

#include "components/runtime/check.h"
#include "components/runtime/random.h"

namespace dmpl {

namespace {

std::vector<double> Numbers(const YAML::Node& node, size_t count, const char* what) {
  if (!node.IsSequence() || node.size() != count) {
    throw std::invalid_argument(std::string("expected ") + what);
  }
  std::vector<double> v;
  for (const auto& e : node) {
    double x = 0.0;
    if (!e.IsScalar() || !YAML::convert<double>::decode(e, x) || !std::isfinite(x)) {
      throw std::invalid_argument(std::string("expected ") + what + " of finite numbers");
    }
    v.push_back(x);
  }
  return v;
}

constexpr uint64_t kGoalStream = 0x676f616c73;  // "goals"

}  // namespace

AxisParam AxisParam::FromYaml(const YAML::Node& node) {
  AxisParam a;
  if (node.IsScalar()) {
    a.name = node.Scalar();
    if (a.name == "x") a.direction = Eigen::Vector3d::UnitX();
    else if (a.name == "y") a.direction = Eigen::Vector3d::UnitY();
    else if (a.name == "z") a.direction = Eigen::Vector3d::UnitZ();
    else throw std::invalid_argument("expected x, y, z or a vector [ax, ay, az]");
    return a;
  }
  const std::vector<double> v = Numbers(node, 3, "x, y, z or a vector [ax, ay, az]");
  a.direction = Eigen::Vector3d(v[0], v[1], v[2]);
  if (a.direction.norm() < 1e-6) throw std::invalid_argument("the axis vector has no length");
  a.direction.normalize();
  a.name.clear();
  return a;
}

YAML::Node AxisParam::ToYaml() const {
  if (!name.empty()) return YAML::Node(name);
  YAML::Node seq(YAML::NodeType::Sequence);
  for (int i = 0; i < 3; ++i) seq.push_back(direction[i]);
  seq.SetStyle(YAML::EmitterStyle::Flow);
  return seq;
}

OrientationParam OrientationParam::FromYaml(const YAML::Node& node) {
  OrientationParam o;
  if (node.IsMap()) {
    if (node.size() != 1 || !node["rpy"]) {
      throw std::invalid_argument("expected [w, x, y, z] or {rpy: [roll, pitch, yaw]}");
    }
    const std::vector<double> r = Numbers(node["rpy"], 3, "rpy: [roll, pitch, yaw]");
    o.q = Eigen::AngleAxisd(r[2], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(r[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r[0], Eigen::Vector3d::UnitX());
    return o;
  }
  const std::vector<double> v =
      Numbers(node, 4, "a quaternion [w, x, y, z] or {rpy: [roll, pitch, yaw]}");
  o.q = Eigen::Quaterniond(v[0], v[1], v[2], v[3]);
  if (o.q.norm() < 1e-6) throw std::invalid_argument("the quaternion has no length");
  o.q.normalize();
  return o;
}

YAML::Node OrientationParam::ToYaml() const {
  YAML::Node seq(YAML::NodeType::Sequence);
  for (double x : {q.w(), q.x(), q.y(), q.z()}) seq.push_back(x);
  seq.SetStyle(YAML::EmitterStyle::Flow);
  return seq;
}

AxisAngle RotationToGoal(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to) {
  Eigen::Quaterniond d = to * from.conjugate();
  if (d.w() < 0) d.coeffs() = -d.coeffs();  // q and -q are one rotation: take the short way
  const double s = d.vec().norm();
  AxisAngle r;
  r.angle = 2.0 * std::atan2(s, d.w());
  if (s > 1e-12) r.axis = d.vec() / s;
  return r;
}

std::vector<Eigen::Quaterniond> RandomGoals(uint64_t seed, int count, double min_separation_rad,
                                            const Eigen::Quaterniond& start) {
  DMPL_DEMAND(count >= 0);
  DMPL_DEMAND(min_separation_rad >= 0 && min_separation_rad <= M_PI);
  Rng rng(seed, 0, kGoalStream);
  std::vector<Eigen::Quaterniond> goals;
  Eigen::Quaterniond last = start.normalized();
  while (static_cast<int>(goals.size()) < count) {
    // Uniform over SO(3) (Shoemake's subgroup algorithm). Half of all rotations lie beyond
    // pi/2 of any given one, so the rejection ends quickly for separations up to about 2.5 rad.
    const double u1 = rng.Uniform(), u2 = 2 * M_PI * rng.Uniform(), u3 = 2 * M_PI * rng.Uniform();
    const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
    const Eigen::Quaterniond q(a * std::sin(u2), a * std::cos(u2), b * std::sin(u3),
                               b * std::cos(u3));
    if (RotationToGoal(last, q).angle < min_separation_rad) continue;
    goals.push_back(q);
    last = q;
  }
  return goals;
}

GoalSequence::GoalSequence(std::vector<Eigen::Quaterniond> goals, double tolerance_rad,
                           double hold_s, double timeout_s)
    : goals_(std::move(goals)), tolerance_(tolerance_rad), hold_(hold_s), timeout_(timeout_s) {
  DMPL_DEMAND(tolerance_rad > 0 && hold_s >= 0);
}

void GoalSequence::Start(double now_s) {
  started_ = now_s;
  within_since_ = -1.0;
}

const Eigen::Quaterniond& GoalSequence::current() const {
  DMPL_DEMAND(!goals_.empty());
  return goals_[std::min(reached_, size() - 1)];
}

GoalSequence::Event GoalSequence::Update(double now_s, const Eigen::Quaterniond& sensed) {
  if (goals_.empty() || complete() || timed_out_) return Event::kNone;
  error_ = RotationToGoal(sensed, goals_[reached_]).angle;
  if (error_ <= tolerance_) {
    if (within_since_ < 0) within_since_ = now_s;
    if (now_s - within_since_ >= hold_) {
      times_.push_back(now_s - started_);
      ++reached_;
      Start(now_s);
      if (!complete()) error_ = RotationToGoal(sensed, goals_[reached_]).angle;
      return Event::kReached;
    }
  } else {
    within_since_ = -1.0;
  }
  if (timeout_ > 0 && now_s - started_ > timeout_) {
    timed_out_ = true;
    return Event::kTimedOut;
  }
  return Event::kNone;
}

}  // namespace dmpl
