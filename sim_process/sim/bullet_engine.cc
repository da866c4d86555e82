#include <algorithm>
#include <cmath>

#include <btBulletDynamicsCommon.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "components/runtime/check.h"
#include "sim_process/sim/physics_engine.h"

// The Bullet engine: the hand as a btMultiBody from the URDF, the object a btRigidBody, in a
// multibody world with the solver settings PyBullet uses for grasping.
namespace dmpl {
namespace {

btVector3 ToBt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d ToEigen(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

btTransform ToBt(const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.linear());
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), ToBt(t.translation()));
}

Eigen::Isometry3d ToEigen(const btTransform& t) {
  const btQuaternion q = t.getRotation();
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).toRotationMatrix();
  out.translation() = ToEigen(t.getOrigin());
  return out;
}

// Diagonal inertia in the link frame; a rotated principal frame is not supported.
btVector3 DiagonalInertia(const LinkInfo& link, const std::string& urdf) {
  const Eigen::Matrix3d& i = link.inertia;
  const double scale = i.diagonal().cwiseAbs().maxCoeff();
  const double off = std::max({std::abs(i(0, 1)), std::abs(i(0, 2)), std::abs(i(1, 2))});
  if (off > 1e-6 * scale) {
    throw ConfigError("URDF error in " + urdf + ": link '" + link.name +
                      "' has an inertia that is not diagonal in the link frame (unsupported)");
  }
  return btVector3(i(0, 0), i(1, 1), i(2, 2));
}

std::unique_ptr<btCollisionShape> MakeShape(const CollisionShape& c, double margin) {
  std::unique_ptr<btConvexShape> shape;
  switch (c.kind) {
    case CollisionShape::Kind::kBox:
      shape = std::make_unique<btBoxShape>(ToBt(c.box_size / 2.0));
      shape->setMargin(margin);
      break;
    case CollisionShape::Kind::kSphere:
      shape = std::make_unique<btSphereShape>(c.radius);  // its margin is its radius
      break;
    case CollisionShape::Kind::kCylinder:
      shape = std::make_unique<btCylinderShapeZ>(btVector3(c.radius, c.radius, c.length / 2.0));
      shape->setMargin(margin);
      break;
  }
  return shape;
}


}  // namespace

// A link collider that also skips the hand's excluded link pairs (hand.self_collision_exclude);
// Bullet itself only knows to skip a link's parent.
class HandLinkCollider : public btMultiBodyLinkCollider {
 public:
  HandLinkCollider(btMultiBody* body, int bullet_link, const HandModel& model)
      : btMultiBodyLinkCollider(body, bullet_link), model_(model) {}
  bool checkCollideWithOverride(const btCollisionObject* co) const override {
    const btMultiBodyLinkCollider* other = btMultiBodyLinkCollider::upcast(co);
    if (other != nullptr && other->m_multiBody == m_multiBody &&
        model_.CollisionExcluded(m_link + 1, other->m_link + 1)) {
      return false;
    }
    return btMultiBodyLinkCollider::checkCollideWithOverride(co);
  }

 private:
  const HandModel& model_;
};

// Everything Bullet, rebuilt by Reset().
struct BulletWorld {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btMultiBodyConstraintSolver solver;
  btMultiBodyDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::unique_ptr<btMultiBody> hand;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyJointLimitConstraint>> limits;
  std::unique_ptr<btRigidBody> object;
  btVector3 object_inertia;
  std::vector<int> bullet_link_of_joint;                    // actuated joint -> Bullet link
  std::vector<std::vector<int>> subtree;                    // actuated joint -> Bullet links
  std::vector<const btCollisionObject*> tip_colliders;      // per finger
  // The fingers' other links (each with its finger): what touches them is truth only.
  std::vector<std::pair<const btCollisionObject*, int>> link_colliders;
  btAlignedObjectArray<btQuaternion> scratch_q;
  btAlignedObjectArray<btVector3> scratch_v;

  ~BulletWorld() {
    if (object) world.removeRigidBody(object.get());
    for (auto& l : limits) world.removeMultiBodyConstraint(l.get());
    for (auto& c : colliders) world.removeCollisionObject(c.get());
    if (hand) world.removeMultiBody(hand.get());
  }
};

class BulletEngine : public PhysicsEngine {
 public:
  explicit BulletEngine(const EngineScene& scene)
      : model_(scene.model),
        sim_(scene.sim),
        object_params_(scene.object),
        object_body_(scene.body),
        palm_pose_(scene.palm_pose) {
    Build();
  }
  ~BulletEngine() override = default;

  void SetJointPositions(const std::vector<double>& q) override;
  JointState Joints() const override;
  std::vector<double> GravityTorques() override;
  void Step(const std::vector<double>& torques) override;
  void SetGravityInPalm(const Eigen::Vector3d& gravity) override;
  Eigen::Vector3d GravityInPalm() const override;
  void ReadTactile(std::vector<TipState>* tips) const override;
  ObjectState Object() const override;
  void HoldObject() override;
  void ReleaseObject() override;
  Eigen::Vector3d TipPosition(int finger) const override;

 private:
  void Build();  // the phases below, in order
  void ConfigureSolver();
  void AddHand();
  void AddHandColliders();
  void AddJointLimits();
  void AddObject();
  void AddLinkForce(const btPersistentManifold& manifold, const btCollisionObject* link, double dt,
                    std::vector<TipState>* tips) const;

  const HandModel& model_;
  SimParams sim_;
  ObjectParams object_params_;
  ObjectBody object_body_;
  Eigen::Isometry3d palm_pose_;
  std::unique_ptr<BulletWorld> world_;
};

// Everything Bullet, in this order (the order is part of the simulation: the same world, the
// same result).
void BulletEngine::Build() {
  world_ = std::make_unique<BulletWorld>();
  ConfigureSolver();
  AddHand();
  AddHandColliders();
  AddJointLimits();
  AddObject();
}

void BulletEngine::ConfigureSolver() {
  BulletWorld& w = *world_;
  const auto& p = sim_.physics;
  w.world.setGravity(btVector3(p.gravity[0], p.gravity[1], p.gravity[2]));
  btContactSolverInfo& info = w.world.getSolverInfo();
  info.m_numIterations = p.solver_iterations;
  info.m_erp2 = p.contact_erp;
  info.m_frictionERP = p.friction_erp;
  info.m_linearSlop = p.linear_slop;
  info.m_minimumSolverBatchSize = p.minimum_solver_batch_size;
  info.m_warmstartingFactor = p.warmstarting_factor;
  info.m_leastSquaresResidualThreshold = p.residual_threshold;
}

// The hand as a fixed-base multibody, one link per URDF link (the palm is the base).
void BulletEngine::AddHand() {
  BulletWorld& w = *world_;
  const auto& p = sim_.physics;
  const auto& links = model_.links();
  const std::string& urdf = model_.urdf_path();
  const int num_links = static_cast<int>(links.size()) - 1;  // the palm is the base
  const LinkInfo& palm = links[0];
  const double palm_mass = palm.mass > 0 ? palm.mass : 1.0;
  const btVector3 palm_inertia =
      palm.mass > 0 ? DiagonalInertia(palm, urdf) : btVector3(1e-3, 1e-3, 1e-3);
  w.hand = std::make_unique<btMultiBody>(num_links, palm_mass, palm_inertia, /*fixedBase=*/true,
                                         /*canSleep=*/false);
  Eigen::Isometry3d base_com = palm_pose_;
  base_com.translate(palm.com);
  w.hand->setBaseWorldTransform(ToBt(base_com));
  for (int l = 1; l <= num_links; ++l) {
    const LinkInfo& link = links[l];
    const JointInfo& joint = model_.joints()[link.parent_joint];
    const LinkInfo& parent = links[link.parent_link];
    const Eigen::Quaterniond parent_to_this(joint.origin.linear().transpose());
    const btQuaternion rot(parent_to_this.x(), parent_to_this.y(), parent_to_this.z(),
                           parent_to_this.w());
    const btVector3 parent_com_to_pivot = ToBt(joint.origin.translation() - parent.com);
    const btVector3 pivot_to_com = ToBt(link.com);
    const btVector3 inertia = DiagonalInertia(link, urdf);
    if (joint.type == JointInfo::Type::kRevolute) {
      w.hand->setupRevolute(l - 1, link.mass, inertia, link.parent_link - 1, rot, ToBt(joint.axis),
                            parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
    } else {
      w.hand->setupFixed(l - 1, link.mass, inertia, link.parent_link - 1, rot,
                         parent_com_to_pivot, pivot_to_com);
    }
  }
  w.hand->finalizeMultiDof();
  w.hand->setLinearDamping(0.0);   // the servos damp the joints; no hidden velocity damping
  w.hand->setAngularDamping(0.0);
  w.hand->setHasSelfCollision(p.self_collision);
  w.world.addMultiBody(w.hand.get());
}

// Colliders: one compound per link, shapes placed relative to the link's centre of mass.
void BulletEngine::AddHandColliders() {
  BulletWorld& w = *world_;
  const auto& p = sim_.physics;
  const auto& links = model_.links();
  const int num_links = static_cast<int>(links.size()) - 1;
  for (int l = 0; l <= num_links; ++l) {
    const LinkInfo& link = links[l];
    if (link.collisions.empty()) continue;
    auto compound = std::make_unique<btCompoundShape>();
    for (const auto& c : link.collisions) {
      Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
      local.translation() = -link.com;
      local = local * c.origin;
      w.shapes.push_back(MakeShape(c, p.collision_margin));
      compound->addChildShape(ToBt(local), w.shapes.back().get());
    }
    auto collider = std::make_unique<HandLinkCollider>(w.hand.get(), l - 1, model_);
    collider->setCollisionShape(compound.get());
    collider->setFriction(sim_.tactile.finger_friction);
    collider->setRollingFriction(0.0);
    collider->setSpinningFriction(0.0);
    collider->setRestitution(0.0);
    w.shapes.push_back(std::move(compound));
    if (l == 0) {
      w.world.addCollisionObject(collider.get(), btBroadphaseProxy::StaticFilter,
                                 btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
      w.hand->setBaseCollider(collider.get());
    } else {
      w.world.addCollisionObject(collider.get(), btBroadphaseProxy::DefaultFilter,
                                 btBroadphaseProxy::AllFilter);
      w.hand->getLink(l - 1).m_collider = collider.get();
    }
    w.colliders.push_back(std::move(collider));
  }
}

// Joint limits, servo bookkeeping, gravity-compensation subtrees, the fingertips' colliders.
void BulletEngine::AddJointLimits() {
  BulletWorld& w = *world_;
  const auto& links = model_.links();
  const std::string& urdf = model_.urdf_path();
  const int num_links = static_cast<int>(links.size()) - 1;
  const int n = model_.num_actuated();
  w.bullet_link_of_joint.resize(n);
  w.subtree.assign(n, {});
  for (int a = 0; a < n; ++a) {
    const JointInfo& joint = model_.actuated_joint(a);
    const int bl = joint.child_link - 1;
    w.bullet_link_of_joint[a] = bl;
    if (std::isfinite(joint.lower) && std::isfinite(joint.upper)) {
      w.limits.push_back(std::make_unique<btMultiBodyJointLimitConstraint>(
          w.hand.get(), bl, joint.lower, joint.upper));
      w.world.addMultiBodyConstraint(w.limits.back().get());
    }
    for (int l = 1; l <= num_links; ++l) {
      for (int k = l; k > 0; k = links[k].parent_link) {
        if (k == joint.child_link) {
          w.subtree[a].push_back(l - 1);
          break;
        }
      }
    }
  }
  w.tip_colliders.clear();
  for (const auto& finger : model_.fingers()) {
    const btMultiBodyLinkCollider* tip = w.hand->getLink(finger.tip_link - 1).m_collider;
    if (tip == nullptr) {
      throw ConfigError("URDF error in " + urdf + ": fingertip link '" +
                        links[finger.tip_link].name + "' has no collision shape to sense with");
    }
    w.tip_colliders.push_back(tip);
  }
  w.link_colliders.clear();
  for (size_t f = 0; f < model_.fingers().size(); ++f) {
    for (const int link : model_.fingers()[f].links) {
      if (link == model_.fingers()[f].tip_link) continue;
      const btMultiBodyLinkCollider* c = w.hand->getLink(link - 1).m_collider;
      if (c != nullptr) w.link_colliders.emplace_back(c, static_cast<int>(f));
    }
  }
}

// A contact of the object with a finger's link other than its tip: its force, as truth (no
// sensor reads it; the controller infers it from the joints' efforts).
void BulletEngine::AddLinkForce(const btPersistentManifold& manifold, const btCollisionObject* link,
                                double dt, std::vector<TipState>* tips) const {
  const auto& colliders = world_->link_colliders;
  const auto it = std::find_if(colliders.begin(), colliders.end(),
                               [link](const auto& c) { return c.first == link; });
  if (it == colliders.end()) return;  // the palm
  for (int i = 0; i < manifold.getNumContacts(); ++i) {
    const double force = manifold.getContactPoint(i).getAppliedImpulse() / dt;
    (*tips)[it->second].link_force += std::max(0.0, force);
  }
}

void BulletEngine::AddObject() {
  BulletWorld& w = *world_;
  const auto& p = sim_.physics;
  const ObjectParams& o = object_params_;
  std::unique_ptr<btCollisionShape> shape;
  if (o.shape == "sphere") {
    shape = std::make_unique<btSphereShape>(o.radius);
  } else if (o.shape == "cylinder") {
    shape = std::make_unique<btCylinderShapeZ>(btVector3(o.radius, o.radius, o.length / 2.0));
  } else if (o.shape == "box") {
    shape = std::make_unique<btBoxShape>(btVector3(o.size[0], o.size[1], o.size[2]) / 2.0);
  } else if (o.shape == "capsule") {
    shape = std::make_unique<btCapsuleShapeZ>(o.radius, o.length);
  } else if (!object_body_.hull.empty()) {  // prism, mesh: their convex hull
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Eigen::Vector3d& v : object_body_.hull) hull->addPoint(ToBt(v), false);
    hull->recalcLocalAabb();
    shape = std::move(hull);
  } else {  // ellipsoid: a unit sphere scaled per axis
    const btVector3 centre(0, 0, 0);
    const btScalar unit = 1.0;
    shape = std::make_unique<btMultiSphereShape>(&centre, &unit, 1);
    shape->setLocalScaling(btVector3(o.radii[0], o.radii[1], o.radii[2]));
  }
  if (o.shape != "sphere") shape->setMargin(p.collision_margin);
  w.object_inertia = ToBt(object_body_.inertia);
  btRigidBody::btRigidBodyConstructionInfo ci(o.mass, nullptr, shape.get(), w.object_inertia);
  ci.m_friction = o.friction;
  ci.m_rollingFriction = o.rolling_friction;
  ci.m_spinningFriction = o.spinning_friction;
  ci.m_restitution = o.restitution;
  ci.m_linearDamping = 0.0;
  ci.m_angularDamping = 0.0;
  ci.m_startWorldTransform = ToBt(palm_pose_ * PoseFromXyzRpy(o.position, o.rpy) * object_body_.principal);
  w.object = std::make_unique<btRigidBody>(ci);
  w.object->setActivationState(DISABLE_DEACTIVATION);
  w.shapes.push_back(std::move(shape));
  w.world.addRigidBody(w.object.get(), btBroadphaseProxy::DefaultFilter,
                       btBroadphaseProxy::AllFilter);
}

void BulletEngine::SetJointPositions(const std::vector<double>& q) {
  DMPL_DEMAND(static_cast<int>(q.size()) == model_.num_actuated());
  BulletWorld& w = *world_;
  for (int a = 0; a < model_.num_actuated(); ++a) {
    w.hand->setJointPos(w.bullet_link_of_joint[a], q[a]);
    w.hand->setJointVel(w.bullet_link_of_joint[a], 0.0);
  }
  w.hand->forwardKinematics(w.scratch_q, w.scratch_v);
  w.hand->updateCollisionObjectWorldTransforms(w.scratch_q, w.scratch_v);
}

JointState BulletEngine::Joints() const {
  const BulletWorld& w = *world_;
  JointState r;
  const int n = model_.num_actuated();
  r.position.resize(n);
  r.velocity.resize(n);
  for (int a = 0; a < n; ++a) {
    const int bl = w.bullet_link_of_joint[a];
    r.position[a] = w.hand->getJointPos(bl);
    r.velocity[a] = w.hand->getJointVel(bl);
  }
  return r;
}

// tau_g = axis . sum over the joint's subtree of (com - pivot) x m g.
std::vector<double> BulletEngine::GravityTorques() {
  BulletWorld& w = *world_;
  btMultiBody& hand = *w.hand;
  const btVector3 g = w.world.getGravity();
  hand.forwardKinematics(w.scratch_q, w.scratch_v);
  std::vector<double> tau(model_.num_actuated(), 0.0);
  for (int a = 0; a < model_.num_actuated(); ++a) {
    const int bl = w.bullet_link_of_joint[a];
    const btTransform& frame = hand.getLink(bl).m_cachedWorldTransform;
    const btVector3 axis = frame.getBasis() * hand.getLink(bl).getAxisTop(0);
    const btVector3 pivot = frame * (-hand.getLink(bl).m_dVector);
    btVector3 moment(0, 0, 0);
    for (int l : w.subtree[a]) {
      const btVector3 com = hand.getLink(l).m_cachedWorldTransform.getOrigin();
      moment += (com - pivot).cross(hand.getLink(l).m_mass * g);
    }
    tau[a] = axis.dot(moment);
  }
  return tau;
}

void BulletEngine::Step(const std::vector<double>& torques) {
  BulletWorld& w = *world_;
  w.hand->clearForcesAndTorques();
  for (int a = 0; a < model_.num_actuated(); ++a) {
    w.hand->addJointTorque(w.bullet_link_of_joint[a], torques[a]);
  }
  const double dt = sim_.physics.time_step;
  w.world.stepSimulation(dt, 0, dt);
}

// The hand stays where it stands in the world; gravity turns the other way.
void BulletEngine::SetGravityInPalm(const Eigen::Vector3d& gravity) {
  world_->world.setGravity(ToBt(Eigen::Vector3d(palm_pose_.linear() * gravity)));
}

Eigen::Vector3d BulletEngine::GravityInPalm() const {
  return palm_pose_.linear().transpose() * ToEigen(world_->world.getGravity());
}

void BulletEngine::ReadTactile(std::vector<TipState>* tips) const {
  BulletWorld& w = *world_;  // Bullet reads its manifolds through non-const calls
  const double dt = sim_.physics.time_step;
  const Eigen::Isometry3d world_to_palm = palm_pose_.inverse();
  const size_t num_fingers = w.tip_colliders.size();
  std::vector<Eigen::Vector3d> weighted_pos(num_fingers, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> weighted_normal(num_fingers, Eigen::Vector3d::Zero());
  tips->assign(num_fingers, TipState{});
  btDispatcher* dispatcher = w.world.getDispatcher();
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
    const btCollisionObject* a = manifold->getBody0();
    const btCollisionObject* b = manifold->getBody1();
    const bool tip_is_a = b == w.object.get();
    if (!tip_is_a && a != w.object.get()) continue;
    const btCollisionObject* tip = tip_is_a ? a : b;
    const auto it = std::find(w.tip_colliders.begin(), w.tip_colliders.end(), tip);
    if (it == w.tip_colliders.end()) {
      AddLinkForce(*manifold, tip, dt, tips);
      continue;
    }
    const size_t f = it - w.tip_colliders.begin();
    TipState& t = (*tips)[f];
    for (int i = 0; i < manifold->getNumContacts(); ++i) {
      const btManifoldPoint& pt = manifold->getContactPoint(i);
      const double force = pt.getAppliedImpulse() / dt;
      if (force <= 0.0) continue;
      // normalWorldOnB points from B to A; we report object -> fingertip.
      const Eigen::Vector3d normal = ToEigen(tip_is_a ? pt.m_normalWorldOnB : -pt.m_normalWorldOnB);
      const Eigen::Vector3d on_object =
          ToEigen(tip_is_a ? pt.getPositionWorldOnB() : pt.getPositionWorldOnA());
      t.force += force;
      t.points += 1;
      weighted_pos[f] += force * on_object;
      weighted_normal[f] += force * normal;
    }
  }
  for (size_t f = 0; f < num_fingers; ++f) {
    TipState& t = (*tips)[f];
    if (t.force <= 0.0) continue;
    t.position = world_to_palm * (weighted_pos[f] / t.force);
    t.normal = (world_to_palm.linear() * weighted_normal[f]).normalized();
  }
}

ObjectState BulletEngine::Object() const {
  const btRigidBody& body = *world_->object;
  const Eigen::Isometry3d world_to_palm = palm_pose_.inverse();
  ObjectState r;
  r.pose = world_to_palm * ToEigen(body.getWorldTransform()) * object_body_.principal.inverse();
  r.linear_velocity = world_to_palm.linear() * ToEigen(body.getLinearVelocity());
  r.angular_velocity = world_to_palm.linear() * ToEigen(body.getAngularVelocity());
  return r;
}

void BulletEngine::HoldObject() {
  BulletWorld& w = *world_;
  btRigidBody& body = *w.object;
  w.world.removeRigidBody(&body);
  body.setMassProps(0.0, btVector3(0, 0, 0));
  body.setCollisionFlags(body.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  body.setLinearVelocity(btVector3(0, 0, 0));
  body.setAngularVelocity(btVector3(0, 0, 0));
  w.world.addRigidBody(&body, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
}

void BulletEngine::ReleaseObject() {
  BulletWorld& w = *world_;
  btRigidBody& body = *w.object;
  w.world.removeRigidBody(&body);
  body.setCollisionFlags(body.getCollisionFlags() & ~btCollisionObject::CF_KINEMATIC_OBJECT);
  body.setMassProps(object_params_.mass, w.object_inertia);
  body.updateInertiaTensor();
  body.setLinearVelocity(btVector3(0, 0, 0));
  body.setAngularVelocity(btVector3(0, 0, 0));
  body.setGravity(w.world.getGravity());
  body.activate(true);
  w.world.addRigidBody(&body, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
}

Eigen::Vector3d BulletEngine::TipPosition(int finger) const {
  const BulletWorld& w = *world_;
  const int bl = model_.fingers()[finger].tip_link - 1;
  const LinkInfo& tip = model_.links()[bl + 1];
  // Link frames in Bullet are at the centre of mass; the tip frame origin is -com from it.
  const btVector3 world = w.hand->localPosToWorld(bl, ToBt(-tip.com));
  return palm_pose_.inverse() * ToEigen(world);
}

std::unique_ptr<PhysicsEngine> MakeBulletEngine(const EngineScene& scene) {
  return std::make_unique<BulletEngine>(scene);
}

}  // namespace dmpl
