// The MuJoCo engine: the hand from the same URDF through MuJoCo's own URDF import, the object a
// free body, in MuJoCo's world, which is the palm frame (the palm is welded to it; gravity turns
// instead of the hand). MuJoCo 2.2.2 (Debian 12) has no model-editing API, so the scene is
// built in MJCF text: the URDF imported with fusestatic off (the fingertips stay bodies of their
// own), saved as MJCF, and the object, options and contact exclusions written into that text.
#include <mujoco/mujoco.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "components/runtime/check.h"
#include "components/runtime/params.h"
#include "sim_process/sim/physics_engine.h"

namespace dmpl {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// A directory of its own for the model's text, removed when done.
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (fs::temp_directory_path() / "dmpl_mujoco_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("cannot create a temporary directory for MuJoCo's model");
    }
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string Num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

std::string Vec(const Eigen::Vector3d& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%.17g %.17g %.17g", v.x(), v.y(), v.z());
  return text;
}

std::string Quat(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  char text[128];
  std::snprintf(text, sizeof text, "%.17g %.17g %.17g %.17g", q.w(), q.x(), q.y(), q.z());
  return text;
}

void InsertAfter(std::string* text, const std::string& anchor, const std::string& what) {
  const size_t at = text->find(anchor);
  DMPL_DEMAND(at != std::string::npos);
  text->insert(at + anchor.size(), what);
}

void InsertBefore(std::string* text, const std::string& anchor, const std::string& what) {
  const size_t at = text->rfind(anchor);
  DMPL_DEMAND(at != std::string::npos);
  text->insert(at, what);
}

// Every unnamed geom of the scene's bodies named (dmpl_geom_<k>): a predefined pair names its
// two geoms, and the URDF importer names none.
void NameGeoms(std::string* xml) {
  int k = 0;
  for (size_t at = xml->find("<geom ", xml->find("<worldbody>")); at != std::string::npos;
       at = xml->find("<geom ", at + 1)) {
    const size_t end = xml->find('>', at);
    DMPL_DEMAND(end != std::string::npos);
    if (xml->substr(at, end - at).find(" name=\"") == std::string::npos) {
      xml->insert(at + 6, "name=\"dmpl_geom_" + std::to_string(k) + "\" ");
    }
    ++k;
  }
}

// MuJoCo's own test (engine_collision_driver.c, mj_contactFilter) of whether two geoms may
// touch: a matching contype/conaffinity, different welded bodies, neither welded to the
// other's parent (unless one is welded to the world), and not excluded.
bool MayTouch(const mjModel* m, int g1, int g2) {
  if (!(m->geom_contype[g1] & m->geom_conaffinity[g2]) &&
      !(m->geom_contype[g2] & m->geom_conaffinity[g1])) {
    return false;
  }
  const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
  const int w1 = m->body_weldid[b1], w2 = m->body_weldid[b2];
  if (w1 == w2) return false;
  const int p1 = m->body_weldid[m->body_parentid[w1]], p2 = m->body_weldid[m->body_parentid[w2]];
  const bool filter_parent = !(m->opt.disableflags & mjDSBL_FILTERPARENT) && w1 && w2;
  if (filter_parent && (w1 == p2 || w2 == p1)) return false;
  const int signature = ((std::min(b1, b2) + 1) << 16) + std::max(b1, b2) + 1;
  for (int e = 0; e < m->nexclude; ++e) {
    if (m->exclude_signature[e] == signature) return false;
  }
  return true;
}

// The <pair> elements of every two geoms that may touch, each with the parameters MuJoCo gives
// a dynamic contact of the two (mj_collideGeoms): the higher priority's condim, friction,
// solref and solimp, or at equal priority the larger condim and friction and solref and solimp
// mixed by solmix; margin and gap the larger.
std::string PredefinedPairs(const mjModel* m) {
  std::string pairs;
  for (int g1 = 0; g1 < m->ngeom; ++g1) {
    for (int g2 = 0; g2 < m->ngeom; ++g2) {
      // Each unordered pair once, the geom of the lower body first (as the broad phase pairs them).
      const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
      if (b1 > b2 || (b1 == b2 && g1 >= g2) || !MayTouch(m, g1, g2)) continue;
      int condim;
      double friction[3], solref[mjNREF], solimp[mjNIMP];
      if (m->geom_priority[g1] != m->geom_priority[g2]) {
        const int g = m->geom_priority[g1] > m->geom_priority[g2] ? g1 : g2;
        condim = m->geom_condim[g];
        for (int i = 0; i < 3; ++i) friction[i] = m->geom_friction[3 * g + i];
        for (int i = 0; i < mjNREF; ++i) solref[i] = m->geom_solref[mjNREF * g + i];
        for (int i = 0; i < mjNIMP; ++i) solimp[i] = m->geom_solimp[mjNIMP * g + i];
      } else {
        condim = std::max(m->geom_condim[g1], m->geom_condim[g2]);
        for (int i = 0; i < 3; ++i) {
          friction[i] = std::max(m->geom_friction[3 * g1 + i], m->geom_friction[3 * g2 + i]);
        }
        const double s1 = m->geom_solmix[g1], s2 = m->geom_solmix[g2];
        double mix = s1 / (s1 + s2);
        if (s1 < mjMINVAL || s2 < mjMINVAL) {
          mix = s1 < mjMINVAL ? (s2 < mjMINVAL ? 0.5 : 0.0) : 1.0;
        }
        const bool standard =
            m->geom_solref[mjNREF * g1] > 0 && m->geom_solref[mjNREF * g2] > 0;
        for (int i = 0; i < mjNREF; ++i) {
          const double r1 = m->geom_solref[mjNREF * g1 + i], r2 = m->geom_solref[mjNREF * g2 + i];
          solref[i] = standard ? mix * r1 + (1 - mix) * r2 : std::min(r1, r2);
        }
        for (int i = 0; i < mjNIMP; ++i) {
          solimp[i] = mix * m->geom_solimp[mjNIMP * g1 + i] +
                      (1 - mix) * m->geom_solimp[mjNIMP * g2 + i];
        }
      }
      std::string refs, imps;
      for (int i = 0; i < mjNREF; ++i) refs += (i ? " " : "") + Num(solref[i]);
      for (int i = 0; i < mjNIMP; ++i) imps += (i ? " " : "") + Num(solimp[i]);
      pairs += std::string("<pair geom1=\"") + mj_id2name(m, mjOBJ_GEOM, g1) + "\" geom2=\"" +
               mj_id2name(m, mjOBJ_GEOM, g2) + "\" condim=\"" + std::to_string(condim) +
               "\" friction=\"" +
               Num(friction[0]) + " " + Num(friction[0]) + " " + Num(friction[1]) + " " +
               Num(friction[2]) + " " + Num(friction[2]) + "\" solref=\"" + refs +
               "\" solimp=\"" + imps + "\" margin=\"" +
               Num(std::max(m->geom_margin[g1], m->geom_margin[g2])) + "\" gap=\"" +
               Num(std::max(m->geom_gap[g1], m->geom_gap[g2])) + "\"/>";
    }
  }
  return pairs;
}

// The object's geom (and, for a hull, its mesh asset), in its principal frame.
std::string ObjectGeom(const ObjectParams& o, const ObjectBody& body, std::string* asset) {
  const auto f = Num;
  if (o.shape == "sphere") return "type=\"sphere\" size=\"" + f(o.radius) + "\"";
  if (o.shape == "cylinder") {
    return "type=\"cylinder\" size=\"" + f(o.radius) + " " + f(o.length / 2) + "\"";
  }
  if (o.shape == "capsule") {
    return "type=\"capsule\" size=\"" + f(o.radius) + " " + f(o.length / 2) + "\"";
  }
  if (o.shape == "box") {
    return "type=\"box\" size=\"" + Vec(Eigen::Vector3d(o.size[0], o.size[1], o.size[2]) / 2) +
           "\"";
  }
  if (o.shape == "ellipsoid") {
    return "type=\"ellipsoid\" size=\"" + Vec({o.radii[0], o.radii[1], o.radii[2]}) + "\"";
  }
  std::string vertices;
  for (const Eigen::Vector3d& v : body.hull) vertices += Vec(v) + " ";
  *asset = "<asset><mesh name=\"dmpl_object\" vertex=\"" + vertices + "\"/></asset>\n";
  return "type=\"mesh\" mesh=\"dmpl_object\"";
}

class MujocoEngine : public PhysicsEngine {
 public:
  explicit MujocoEngine(const EngineScene& scene)
      : model_(scene.model), sim_(scene.sim), object_(scene.object) {
    m_ = Compile(scene);
    d_ = mj_makeData(m_);
    FindIndices(scene);
    held_pose_.assign(d_->qpos + object_qpos_, d_->qpos + object_qpos_ + 7);
  }
  ~MujocoEngine() override {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }

  void SetJointPositions(const std::vector<double>& q) override {
    DMPL_DEMAND(static_cast<int>(q.size()) == model_.num_actuated());
    for (int a = 0; a < model_.num_actuated(); ++a) {
      d_->qpos[joint_qpos_[a]] = q[a];
      d_->qvel[joint_dof_[a]] = 0.0;
    }
    mj_kinematics(m_, d_);
    begun_ = false;
  }

  JointState Joints() const override {
    JointState r;
    for (int a = 0; a < model_.num_actuated(); ++a) {
      r.position.push_back(d_->qpos[joint_qpos_[a]]);
      r.velocity.push_back(d_->qvel[joint_dof_[a]]);
    }
    return r;
  }

  // tau_g = axis . sum over the joint's subtree of (com - anchor) x m g, from the kinematics of
  // the step's first half (mj_step1), which Step() completes: no second pass of kinematics.
  std::vector<double> GravityTorques() override {
    BeginStep();
    const Eigen::Map<const Eigen::Vector3d> g(m_->opt.gravity);
    std::vector<double> tau(model_.num_actuated(), 0.0);
    for (int a = 0; a < model_.num_actuated(); ++a) {
      const int j = joint_id_[a];
      const Eigen::Map<const Eigen::Vector3d> axis(d_->xaxis + 3 * j), anchor(d_->xanchor + 3 * j);
      Eigen::Vector3d moment = Eigen::Vector3d::Zero();
      for (const int b : subtree_[a]) {
        const Eigen::Map<const Eigen::Vector3d> com(d_->xipos + 3 * b);
        moment += (com - anchor).cross(m_->body_mass[b] * g);
      }
      tau[a] = axis.dot(moment);
    }
    return tau;
  }

  void Step(const std::vector<double>& torques) override {
    BeginStep();
    mju_zero(d_->qfrc_applied, m_->nv);
    for (int a = 0; a < model_.num_actuated(); ++a) d_->qfrc_applied[joint_dof_[a]] = torques[a];
    mj_step2(m_, d_);
    begun_ = false;
    if (held_) Pin();
  }

  void SetGravityInPalm(const Eigen::Vector3d& gravity) override {
    Eigen::Map<Eigen::Vector3d>(m_->opt.gravity) = gravity;
  }
  Eigen::Vector3d GravityInPalm() const override {
    return Eigen::Map<const Eigen::Vector3d>(m_->opt.gravity);
  }

  void ReadTactile(std::vector<TipState>* tips) const override {
    const size_t num_fingers = model_.fingers().size();
    std::vector<Eigen::Vector3d> weighted_pos(num_fingers, Eigen::Vector3d::Zero());
    std::vector<Eigen::Vector3d> weighted_normal(num_fingers, Eigen::Vector3d::Zero());
    tips->assign(num_fingers, TipState{});
    for (int i = 0; i < d_->ncon; ++i) {
      const mjContact& c = d_->contact[i];
      const int b1 = m_->geom_bodyid[c.geom1], b2 = m_->geom_bodyid[c.geom2];
      if (b1 != object_body_ && b2 != object_body_) continue;
      const bool object_first = b1 == object_body_;
      const int other = object_first ? b2 : b1;
      mjtNum wrench[6];
      mj_contactForce(m_, d_, i, wrench);
      const double force = wrench[0];
      if (force <= 0.0) continue;
      const auto finger = finger_of_body_.find(other);
      if (finger == finger_of_body_.end()) continue;  // the palm
      TipState& t = (*tips)[finger->second.first];
      if (!finger->second.second) {
        t.link_force += force;
        continue;
      }
      // The frame's first row is the normal from geom1 to geom2; pos lies midway between the
      // surfaces, `dist` apart.
      const Eigen::Map<const Eigen::Vector3d> n(c.frame), pos(c.pos);
      const Eigen::Vector3d normal = object_first ? Eigen::Vector3d(n) : Eigen::Vector3d(-n);
      const Eigen::Vector3d on_object = pos - normal * (c.dist / 2);
      t.force += force;
      t.points += 1;
      weighted_pos[finger->second.first] += force * on_object;
      weighted_normal[finger->second.first] += force * normal;
    }
    for (size_t f = 0; f < num_fingers; ++f) {
      TipState& t = (*tips)[f];
      if (t.force <= 0.0) continue;
      t.position = weighted_pos[f] / t.force;
      t.normal = weighted_normal[f].normalized();
    }
  }

  ObjectState Object() const override {
    const mjtNum* q = d_->qpos + object_qpos_;
    const mjtNum* v = d_->qvel + object_dof_;
    ObjectState r;
    Eigen::Isometry3d principal = Eigen::Isometry3d::Identity();
    principal.translation() = Eigen::Vector3d(q[0], q[1], q[2]);
    principal.linear() = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized().toRotationMatrix();
    r.pose = principal * principal_.inverse();
    r.linear_velocity = Eigen::Vector3d(v[0], v[1], v[2]);
    // A free joint's angular velocity is in the body's frame.
    r.angular_velocity = principal.linear() * Eigen::Vector3d(v[3], v[4], v[5]);
    return r;
  }

  // Held, the object is as heavy as a wall to the contact solver (Bullet makes it kinematic):
  // with its own 50 g within each step, a link pressing on it moved it before Pin() put it
  // back, and the fingers closing on a 10 cm standing cylinder never all touched it at once.
  void HoldObject() override {
    held_pose_.assign(d_->qpos + object_qpos_, d_->qpos + object_qpos_ + 7);
    held_ = true;
    SetObjectArmature(kHeldArmature);
    Pin();
    begun_ = false;
  }
  void ReleaseObject() override {
    held_ = false;
    SetObjectArmature(0.0);
    mju_zero(d_->qvel + object_dof_, 6);
    begun_ = false;
  }

  Eigen::Vector3d TipPosition(int finger) const override {
    mj_kinematics(m_, d_);
    return Eigen::Map<const Eigen::Vector3d>(d_->xpos + 3 * tip_body_[finger]);
  }

 private:
  mjModel* Compile(const EngineScene& scene);
  void FindIndices(const EngineScene& scene);
  // The half of a step that depends on positions and velocities only (kinematics, contacts);
  // Euler's mj_step1 + mj_step2 is mj_step.
  void BeginStep() {
    if (begun_) return;
    if (held_) Pin();
    mj_step1(m_, d_);
    begun_ = true;
  }
  static constexpr double kHeldArmature = 1e4;  // kg, kg*m^2: added to the object's six dofs
  void SetObjectArmature(double armature) {
    for (int i = 0; i < 6; ++i) m_->dof_armature[object_dof_ + i] = armature;
  }
  // Held "by a person": the object where it was held, at rest.
  void Pin() {
    std::copy(held_pose_.begin(), held_pose_.end(), d_->qpos + object_qpos_);
    mju_zero(d_->qvel + object_dof_, 6);
  }

  const HandModel& model_;
  const SimParams sim_;
  const ObjectParams object_;
  Eigen::Isometry3d principal_ = Eigen::Isometry3d::Identity();
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<int> joint_id_, joint_qpos_, joint_dof_;  // per actuated joint
  std::vector<std::vector<int>> subtree_;               // per actuated joint: bodies it carries
  std::vector<int> tip_body_;                           // per finger
  std::map<int, std::pair<int, bool>> finger_of_body_;  // body -> (finger, is its tip)
  int object_body_ = -1, object_qpos_ = -1, object_dof_ = -1;
  std::vector<double> held_pose_;
  bool held_ = false;
  bool begun_ = false;  // mj_step1 done, mj_step2 to come
};

mjModel* MujocoEngine::Compile(const EngineScene& scene) {
  const std::string at = "config error in " + scene.source + ": key 'sim.engine': MuJoCo ";
  char error[1000] = "";
  ScratchDir dir;
  // 1. The URDF, with the compiler settings that keep the fingertips as bodies of their own.
  std::string urdf = ReadText(model_.urdf_path());
  const size_t robot = urdf.find("<robot");
  const size_t robot_end = robot == std::string::npos ? robot : urdf.find('>', robot);
  if (robot_end == std::string::npos) {
    throw ConfigError(at + "found no <robot> element in " + model_.urdf_path());
  }
  urdf.insert(robot_end + 1,
              "<mujoco><compiler fusestatic=\"false\" discardvisual=\"true\"/></mujoco>");
  WriteText(dir.path() / "hand.urdf", urdf);
  mjModel* hand = mj_loadXML((dir.path() / "hand.urdf").c_str(), nullptr, error, sizeof error);
  if (hand == nullptr) {
    throw ConfigError(at + "could not import " + model_.urdf_path() + ": " + error);
  }
  const int saved = mj_saveLastXML((dir.path() / "hand.xml").c_str(), hand, error, sizeof error);
  mj_deleteModel(hand);
  if (!saved) throw ConfigError(at + "could not save the imported hand: " + error);

  // 2. The scene: options, defaults, the object, contact exclusions.
  std::string xml = ReadText(dir.path() / "hand.xml");
  const SimParams& sim = scene.sim;
  const MujocoParams& mj = sim.mujoco;
  const auto& g = sim.physics.gravity;
  const Eigen::Vector3d gravity =
      scene.palm_pose.linear().transpose() * Eigen::Vector3d(g[0], g[1], g[2]);
  const std::string hand_affinity = sim.physics.self_collision ? "1" : "2";
  InsertAfter(&xml, "autolimits=\"true\"/>",
              "\n  <option timestep=\"" + Num(sim.physics.time_step) +
                  "\" gravity=\"" + Vec(gravity) + "\" cone=\"" + mj.cone +
                  "\" integrator=\"Euler\" iterations=\"" + std::to_string(mj.iterations) +
                  "\" noslip_iterations=\"" + std::to_string(mj.noslip_iterations) +
                  "\" impratio=\"" + Num(mj.impratio) + "\"/>");
  const std::string defaults =
      "<default><joint damping=\"" + Num(mj.joint_damping) +
      "\"/><geom contype=\"1\" conaffinity=\"" + hand_affinity + "\" friction=\"" +
      Num(sim.tactile.finger_friction) + " 0 0\" solref=\"" +
      Num(mj.solref[0]) + " " + Num(mj.solref[1]) + "\" solimp=\"" + Num(mj.solimp[0]) + " " +
      Num(mj.solimp[1]) + " " + Num(mj.solimp[2]) + "\"/></default>";
  if (xml.find("<default/>") != std::string::npos) {
    xml.replace(xml.find("<default/>"), 10, defaults);
  } else {
    InsertBefore(&xml, "<worldbody>", defaults + "\n  ");
  }
  const ObjectParams& o = scene.object;
  principal_ = scene.body.principal;
  const Eigen::Isometry3d start = PoseFromXyzRpy(o.position, o.rpy) * scene.body.principal;
  std::string asset;
  const std::string geom = ObjectGeom(o, scene.body, &asset);
  // The object's friction wins at its contacts (priority), as Bullet's product of the two.
  char friction[128];
  std::snprintf(friction, sizeof friction, "%.17g %.17g %.17g",
                o.friction * sim.tactile.finger_friction, mj.torsional_friction,
                mj.rolling_friction);
  InsertBefore(&xml, "</worldbody>",
               "  <body name=\"dmpl_object\" pos=\"" + Vec(start.translation()) + "\" quat=\"" +
                   Quat(start.linear()) + "\">\n      <freejoint/>\n      <inertial pos=\"0 0 0\" "
                   "mass=\"" + Num(o.mass) + "\" diaginertia=\"" +
                   Vec(scene.body.inertia) + "\"/>\n      <geom " + geom +
                   " priority=\"1\" condim=\"" + std::to_string(mj.contact_dimension()) +
                   "\" contype=\"1\" conaffinity=\"1\" friction=\"" +
                   friction + "\"/>\n    </body>\n  ");
  if (!asset.empty()) InsertBefore(&xml, "<worldbody>", asset + "  ");
  std::string exclude;
  const auto& links = model_.links();
  for (size_t a = 0; a < links.size(); ++a) {
    for (size_t b = a + 1; b < links.size(); ++b) {
      // A link never touches its parent, as in Bullet; MuJoCo would keep the palm's children
      // (the palm is welded to the world, and it filters no contact with the world).
      const bool parent = links[b].parent_link == static_cast<int>(a);
      if (!parent && !model_.CollisionExcluded(a, b)) continue;
      exclude += "<exclude body1=\"" + links[a].name + "\" body2=\"" + links[b].name + "\"/>";
    }
  }
  InsertAfter(&xml, "</worldbody>", "\n  <contact>" + exclude + "</contact>");
  NameGeoms(&xml);
  auto compile = [&] {
    WriteText(dir.path() / "scene.xml", xml);
    mjModel* m = mj_loadXML((dir.path() / "scene.xml").c_str(), nullptr, error, sizeof error);
    if (m == nullptr) throw ConfigError(at + "could not compile the scene: " + error);
    return m;
  };
  mjModel* m = compile();
  if (mj.collision == "dynamic") return m;
  // 3. The pairs the broad phase could find, listed once; the model compiled again with them.
  const std::string pairs = PredefinedPairs(m);
  mj_deleteModel(m);
  InsertBefore(&xml, "</contact>", pairs);
  InsertAfter(&xml, "<option ", "collision=\"predefined\" ");
  return compile();
}

void MujocoEngine::FindIndices(const EngineScene& scene) {
  const std::string urdf = model_.urdf_path();
  auto id = [&](mjtObj type, const std::string& name) {
    const int i = mj_name2id(m_, type, name.c_str());
    if (i < 0) {
      throw ConfigError("config error in " + scene.source + ": key 'sim.engine': MuJoCo's import of " +
                        urdf + " has no '" + name + "'");
    }
    return i;
  };
  for (int a = 0; a < model_.num_actuated(); ++a) {
    const int j = id(mjOBJ_JOINT, model_.actuated_joint(a).name);
    joint_id_.push_back(j);
    joint_qpos_.push_back(m_->jnt_qposadr[j]);
    joint_dof_.push_back(m_->jnt_dofadr[j]);
    const int body = m_->jnt_bodyid[j];
    subtree_.emplace_back();
    for (int b = 1; b < m_->nbody; ++b) {
      for (int k = b; k > 0; k = m_->body_parentid[k]) {
        if (k == body) {
          subtree_.back().push_back(b);
          break;
        }
      }
    }
  }
  for (size_t f = 0; f < model_.fingers().size(); ++f) {
    const FingerInfo& finger = model_.fingers()[f];
    tip_body_.push_back(id(mjOBJ_BODY, model_.links()[finger.tip_link].name));
    for (const int link : finger.links) {
      finger_of_body_[id(mjOBJ_BODY, model_.links()[link].name)] = {static_cast<int>(f),
                                                                   link == finger.tip_link};
    }
  }
  object_body_ = id(mjOBJ_BODY, "dmpl_object");
  const int free = m_->body_jntadr[object_body_];
  object_qpos_ = m_->jnt_qposadr[free];
  object_dof_ = m_->jnt_dofadr[free];
}

}  // namespace

std::unique_ptr<PhysicsEngine> MakeMujocoEngine(const EngineScene& scene) {
  return std::make_unique<MujocoEngine>(scene);
}

}  // namespace dmpl
