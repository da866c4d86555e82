#include "sim_process/sim/hand_sim.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "components/runtime/check.h"
#include "components/hand/hand_params.h"
#include "sim_process/sim/convex_object.h"

namespace dmpl {
namespace {

}  // namespace

Eigen::Vector3d ObjectInertia(const ObjectParams& o) {
  const double m = o.mass;
  if (o.shape == "sphere") {
    const double i = 0.4 * m * o.radius * o.radius;
    return {i, i, i};
  }
  if (o.shape == "cylinder") {
    const double r2 = o.radius * o.radius, h2 = o.length * o.length;
    const double ixy = m * (3.0 * r2 + h2) / 12.0;
    return {ixy, ixy, 0.5 * m * r2};
  }
  if (o.shape == "box") {
    const double x2 = o.size[0] * o.size[0], y2 = o.size[1] * o.size[1],
                 z2 = o.size[2] * o.size[2];
    return {m * (y2 + z2) / 12.0, m * (x2 + z2) / 12.0, m * (x2 + y2) / 12.0};
  }
  if (o.shape == "ellipsoid") {
    const double a2 = o.radii[0] * o.radii[0], b2 = o.radii[1] * o.radii[1],
                 c2 = o.radii[2] * o.radii[2];
    return {m * (b2 + c2) / 5.0, m * (a2 + c2) / 5.0, m * (a2 + b2) / 5.0};
  }
  if (o.shape == "capsule") {
    // Cylinder of length L plus two hemispheres of radius r, uniform density, axis z.
    const double r = o.radius, l = o.length;
    const double v_cyl = M_PI * r * r * l, v_sph = 4.0 / 3.0 * M_PI * r * r * r;
    const double m_cyl = m * v_cyl / (v_cyl + v_sph), m_sph = m - m_cyl;
    const double izz = m_cyl * r * r / 2.0 + m_sph * 2.0 * r * r / 5.0;
    const double ixx = m_cyl * (3.0 * r * r + l * l) / 12.0 +
                       m_sph * (2.0 * r * r / 5.0 + l * l / 4.0 + 3.0 * l * r / 8.0);
    return {ixx, ixx, izz};
  }
  throw ConfigError("config error: key 'object.shape': unknown shape '" + o.shape + "'");
}

ObjectBody MakeObjectBody(const ObjectParams& o, const std::string& source) {
  ObjectBody body;
  if (o.shape != "prism" && o.shape != "mesh") {
    body.inertia = ObjectInertia(o);
    return body;
  }
  const std::string key = o.shape == "mesh" ? "mesh" : "sides";
  auto fail = [&](const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'object." + key + "': " + what);
  };
  Mesh mesh;
  ConvexHull hull;
  try {
    if (o.shape == "prism") {
      mesh.points = PrismPoints(o.sides, o.radius, o.length);
    } else {
      mesh = ReadMesh(ResolveProjectPath(o.mesh));
      for (Eigen::Vector3d& p : mesh.points) p *= o.scale;
    }
    hull = HullOf(mesh.points);
  } catch (const std::runtime_error& e) {
    fail(e.what());
  }
  Eigen::AlignedBox3d box;
  for (const auto& v : hull.vertices) box.extend(v);
  const double size = box.diagonal().norm();
  if (const double depth = DeepestTriangle(mesh, hull); depth > 1e-3 * size) {
    fail("not convex: a face lies " + std::to_string(depth * 1000) +
         " mm inside the mesh's convex hull (dmpl simulates a mesh as its convex hull)");
  }
  if (size > 0.5) fail("a mesh " + std::to_string(size) + " m across (object.scale: its unit?)");
  const MassProperties mass = MassOf(hull, o.mass);
  // The principal axes, right-handed, ordered by Eigen (ascending moments).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(mass.inertia);
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  body.principal.linear() = axes;
  body.principal.translation() = mass.centroid;
  body.inertia = eig.eigenvalues();
  const Eigen::Isometry3d to_principal = body.principal.inverse();
  for (const auto& v : hull.vertices) body.hull.push_back(to_principal * v);
  return body;
}


void SimParams::Validate(const std::string& source) const {
  CheckBounds(*this, source, "sim");
  if (servo.kp.empty() || servo.kp.size() != servo.kd.size()) {
    throw ConfigError("config error in " + source +
                      ": key 'sim.servo.kp': kp and kd need the same, non-zero number of entries");
  }
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'sim." + key + "': " + what);
  };
  if (engine != "bullet" && engine != "mujoco") {
    fail("engine", "unknown engine '" + engine + "' (bullet, mujoco)");
  }
  if (mujoco.cone != "pyramidal" && mujoco.cone != "elliptic") {
    fail("mujoco.cone", "'" + mujoco.cone + "' is not pyramidal or elliptic");
  }
  if (mujoco.collision != "dynamic" && mujoco.collision != "predefined") {
    fail("mujoco.collision", "'" + mujoco.collision + "' is not dynamic or predefined");
  }
  if (!(mujoco.solref[0] > 0) || !(mujoco.solref[1] > 0)) {
    fail("mujoco.solref", "time constant and damping ratio must be > 0");
  }
  // MuJoCo would silently stiffen a faster contact to two steps (its refsafe rule).
  if (engine == "mujoco" && mujoco.solref[0] < 2 * physics.time_step) {
    fail("mujoco.solref", "a time constant of " + std::to_string(mujoco.solref[0]) +
                              " s is under two steps (sim.physics.time_step " +
                              std::to_string(physics.time_step) + " s): MuJoCo cannot follow it");
  }
  if (!(mujoco.solimp[0] > 0 && mujoco.solimp[0] <= mujoco.solimp[1] && mujoco.solimp[1] < 1 &&
        mujoco.solimp[2] > 0)) {
    fail("mujoco.solimp", "needs 0 < dmin <= dmax < 1 and a width > 0");
  }
}

void ObjectParams::Validate(const std::string& source) const {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw ConfigError("config error in " + source + ": key 'object." + key + "': " + what);
  };
  CheckBounds(*this, source, "object");
  static const std::vector<std::string> kShapes = {"sphere", "cylinder", "box", "capsule",
                                                   "ellipsoid", "prism", "mesh"};
  if (std::find(kShapes.begin(), kShapes.end(), shape) == kShapes.end()) {
    fail("shape", "unknown shape '" + shape +
                      "' (sphere, cylinder, box, capsule, ellipsoid, prism, mesh)");
  }
  if ((shape == "sphere" || shape == "cylinder" || shape == "capsule" || shape == "prism") &&
      !(radius > 0)) {
    fail("radius", "must be > 0");
  }
  if ((shape == "cylinder" || shape == "capsule" || shape == "prism") && !(length > 0)) {
    fail("length", "must be > 0");
  }
  if (shape == "mesh" && mesh.empty()) fail("mesh", "a mesh object needs its file (.obj or .stl)");
  if (shape == "box") for (double s : size) if (!(s > 0)) fail("size", "edges must be > 0");
  if (shape == "ellipsoid") for (double r : radii) if (!(r > 0)) fail("radii", "must be > 0");
}

HandSim::HandSim(const HandModel& model, const SimParams& sim, const ObjectParams& object,
                 const std::string& source)
    : model_(model),
      source_(source),
      sim_(sim),
      object_params_(object),
      palm_pose_(PoseFromXyzRpy(sim.palm_position, sim.palm_rpy)),
      palm_motion_(sim.palm_motion, palm_pose_.linear(), source) {
  sim_.Validate(source);
  object_params_.Validate(source);
  object_body_ = MakeObjectBody(object_params_, source);
  for (const auto& [finger, q] : sim_.initial_joints) {
    const std::string at = "config error in " + source + ": key 'sim.initial_joints." + finger;
    const int f = model_.FindFinger(finger);
    if (f < 0) throw ConfigError(at + "': no such finger");
    if (q.size() != model_.fingers()[f].joints.size()) {
      throw ConfigError(at + "': expected " +
                        std::to_string(model_.fingers()[f].joints.size()) + " joint angles");
    }
  }
  Build();
}

HandSim::~HandSim() = default;

void HandSim::Reset() { Build(); }

void HandSim::Build() {
  const EngineScene scene{model_, sim_, object_params_, object_body_, palm_pose_, source_};
  engine_ = sim_.engine == "mujoco" ? MakeMujocoEngine(scene) : MakeBulletEngine(scene);
  SetInitialState();
}

// Initial joints: from the config, else zero clamped into the limits; the object held or not.
void HandSim::SetInitialState() {
  const int n = model_.num_actuated();
  std::vector<double> q(n, 0.0);
  for (int a = 0; a < n; ++a) {
    const JointInfo& joint = model_.actuated_joint(a);
    q[a] = std::clamp(0.0, joint.lower, joint.upper);
  }
  for (const auto& [finger, angles] : sim_.initial_joints) {
    const FingerInfo& f = model_.fingers()[model_.FindFinger(finger)];
    for (size_t i = 0; i < angles.size(); ++i) q[f.joints[i]] = angles[i];
  }
  SetJointPositions(q);
  held_ = false;
  if (object_params_.held) HoldObject();
  tactile_.assign(model_.fingers().size(), TipState{});
  time_ = 0.0;
  steps_ = 0;
}

void HandSim::SetJointPositions(const std::vector<double>& q) {
  DMPL_DEMAND(static_cast<int>(q.size()) == model_.num_actuated());
  engine_->SetJointPositions(q);
  targets_ = q;
  effort_.assign(q.size(), 0.0);
}

bool HandSim::SetJointTargets(const std::vector<double>& q, std::string* why) {
  if (static_cast<int>(q.size()) != model_.num_actuated()) {
    *why = "expected " + std::to_string(model_.num_actuated()) + " joint targets, got " +
           std::to_string(q.size());
    return false;
  }
  for (int a = 0; a < model_.num_actuated(); ++a) {
    const JointInfo& joint = model_.actuated_joint(a);
    if (!std::isfinite(q[a])) {
      *why = "joint '" + joint.name + "' target is not finite";
      return false;
    }
    // A hair of tolerance for targets computed exactly at a limit.
    if (q[a] < joint.lower - 1e-9 || q[a] > joint.upper + 1e-9) {
      *why = "joint '" + joint.name + "' target " + std::to_string(q[a]) + " is outside [" +
             std::to_string(joint.lower) + ", " + std::to_string(joint.upper) + "]";
      return false;
    }
  }
  targets_ = q;
  return true;
}

// tau = scale (kp (q* - q) - kd qd) - tau_gravity, clamped to the URDF's effort limit.
void HandSim::ApplyServoTorques() {
  const auto& servo = sim_.servo;
  const JointState now = engine_->Joints();
  const std::vector<double> gravity =
      servo.gravity_compensation ? engine_->GravityTorques() : std::vector<double>{};
  for (const FingerInfo& finger : model_.fingers()) {
    const auto scale_it = servo.finger_scale.find(finger.name);
    const double scale = scale_it == servo.finger_scale.end() ? 1.0 : scale_it->second;
    for (size_t k = 0; k < finger.joints.size(); ++k) {
      const int a = finger.joints[k];
      const size_t gain = std::min(k, servo.kp.size() - 1);
      double tau = scale * (servo.kp[gain] * (targets_[a] - now.position[a]) -
                            servo.kd[gain] * now.velocity[a]);
      if (servo.gravity_compensation) tau -= gravity[a];
      const double limit = model_.actuated_joint(a).effort;
      effort_[a] = std::clamp(tau, -limit, limit);
    }
  }
}

Eigen::Vector3d HandSim::gravity_in_palm() const { return engine_->GravityInPalm(); }

void HandSim::TurnGravity() {
  if (!palm_motion_.moves()) return;
  const auto& g = sim_.physics.gravity;
  engine_->SetGravityInPalm(palm_motion_.GravityInPalm(time_, Eigen::Vector3d(g[0], g[1], g[2])));
}

void HandSim::Step() {
  TurnGravity();
  ApplyServoTorques();
  engine_->Step(effort_);
  time_ += sim_.physics.time_step;
  ++steps_;
  ReadTactile();
}

void HandSim::ReadTactile() {
  engine_->ReadTactile(&tactile_);
  for (TipState& t : tactile_) t.in_contact = t.force > sim_.tactile.contact_threshold_n;
}

JointState HandSim::joints() const {
  JointState r = engine_->Joints();
  r.effort = effort_;
  return r;
}

ObjectState HandSim::object() const { return engine_->Object(); }

void HandSim::HoldObject() {
  engine_->HoldObject();
  held_ = true;
}

void HandSim::ReleaseObject() {
  engine_->ReleaseObject();
  held_ = false;
}

Eigen::Vector3d HandSim::TipPosition(int finger) const { return engine_->TipPosition(finger); }

}  // namespace dmpl
