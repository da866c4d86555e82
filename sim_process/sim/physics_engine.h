#pragma once
// The seam between the simulator and a physics engine. HandSim owns what every engine shares
// (the parameters, the servo law, the palm's motion, time, the tactile threshold); an engine owns
// its world: the hand from the URDF, the object, contacts. Everything crosses in the palm frame.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/hand/hand_model.h"
#include "sim_process/sim/sim_params.h"

namespace dmpl {

struct JointState {
  std::vector<double> position, velocity, effort;  // actuated joints, HandModel order
};

struct ObjectState {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // palm frame
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
};

struct TipState {
  bool in_contact = false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // force-weighted contact point on the object
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();    // object -> fingertip
  double force = 0.0;                                  // normal force, N
  int points = 0;
  double link_force = 0.0;  // on the finger's other links, N: truth that no sensor reads
};

// The object as the physics holds it: the principal frame of its inertia (at its centre of mass)
// in the frame its pose is given in, the inertia's diagonal there, and, for a shape given by
// points (prism, mesh), its convex hull's vertices in that frame.
struct ObjectBody {
  Eigen::Isometry3d principal = Eigen::Isometry3d::Identity();  // object <- principal
  Eigen::Vector3d inertia = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> hull;  // empty: a primitive shape
};

// What an engine is built from: the validated parameters and the hand's place in its world.
struct EngineScene {
  const HandModel& model;
  const SimParams& sim;
  const ObjectParams& object;
  const ObjectBody& body;
  Eigen::Isometry3d palm_pose;  // where the hand stands in the world (sim.palm_position, _rpy)
  std::string source;           // names the config in errors
};

class PhysicsEngine {
 public:
  virtual ~PhysicsEngine() = default;

  // Teleports the actuated joints, velocities zero.
  virtual void SetJointPositions(const std::vector<double>& q) = 0;
  // Positions and velocities of the actuated joints (effort is HandSim's).
  virtual JointState Joints() const = 0;
  // Per actuated joint, the torque gravity exerts on the links it carries, now: what a
  // gravity-compensating servo cancels.
  virtual std::vector<double> GravityTorques() = 0;
  // One step of physics.time_step with these joint torques.
  virtual void Step(const std::vector<double>& torques) = 0;

  virtual void SetGravityInPalm(const Eigen::Vector3d& gravity) = 0;
  virtual Eigen::Vector3d GravityInPalm() const = 0;

  // The contacts of the last step, per finger (in_contact is HandSim's to decide).
  virtual void ReadTactile(std::vector<TipState>* tips) const = 0;
  virtual ObjectState Object() const = 0;
  // Held: fixed where it is, "by a person"; released: free under gravity and contacts.
  virtual void HoldObject() = 0;
  virtual void ReleaseObject() = 0;
  // The tip link's origin, palm frame.
  virtual Eigen::Vector3d TipPosition(int finger) const = 0;
};

std::unique_ptr<PhysicsEngine> MakeBulletEngine(const EngineScene& scene);
// Throws ConfigError naming the key and MuJoCo's own message when its model does not compile.
std::unique_ptr<PhysicsEngine> MakeMujocoEngine(const EngineScene& scene);

}  // namespace dmpl
