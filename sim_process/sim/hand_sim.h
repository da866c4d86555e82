#pragma once
// The simulator's core: the hand from the URDF and one object in a physics engine (sim.engine:
// Bullet, the default, or MuJoCo; physics_engine.h), with joint servos of bounded stiffness and
// fingertip tactile sensing. No LCM here. Everything it reports is in the palm frame.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "components/hand/hand_model.h"
#include "sim_process/sim/physics_engine.h"
#include "sim_process/sim/sim_params.h"

namespace dmpl {

class HandSim {
 public:
  // Validates the parameters (the one place they are): throws ConfigError naming `source` and the
  // key on invalid ones (unknown shape or engine, non-positive mass, an initial pose of an unknown
  // finger, a model the engine cannot compile).
  HandSim(const HandModel& model, const SimParams& sim, const ObjectParams& object,
          const std::string& source = "the simulator's parameters");
  ~HandSim();
  HandSim(const HandSim&) = delete;
  HandSim& operator=(const HandSim&) = delete;

  // Sets the servo targets (one per actuated joint). Rejects, and leaves the previous targets in
  // place, when the size is wrong, a value is not finite, or a value is outside the joint limits.
  bool SetJointTargets(const std::vector<double>& q, std::string* why);
  const std::vector<double>& joint_targets() const { return targets_; }

  // One physics step of physics.time_step.
  void Step();

  double time() const { return time_; }
  int64_t steps() const { return steps_; }
  JointState joints() const;
  ObjectState object() const;
  const std::vector<TipState>& tactile() const { return tactile_; }

  void ReleaseObject();
  void HoldObject();
  bool object_held() const { return held_; }
  // Back to the initial scenario (joints, object, time).
  void Reset();

  const HandModel& model() const { return model_; }
  const Eigen::Isometry3d& palm_pose() const { return palm_pose_; }
  // Gravity in the palm frame now (m/s^2): what an IMU on the palm reads. It turns as the palm
  // does (sim.palm_motion).
  Eigen::Vector3d gravity_in_palm() const;
  // The palm's orientation in the world now (sim.palm_rpy, turned by sim.palm_motion).
  Eigen::Matrix3d palm_orientation() const { return palm_motion_.Orientation(time_); }
  // Fingertip (tip link origin) positions in the palm frame, from the simulator's own state.
  Eigen::Vector3d TipPosition(int finger) const;
  // Teleports the joints (velocities zero) and sets the targets to match. For tests and setup.
  void SetJointPositions(const std::vector<double>& q);

 private:
  void Build();  // the engine's world, then the initial state
  void SetInitialState();
  void ApplyServoTorques();
  void TurnGravity();  // as the palm turns (sim.palm_motion)
  void ReadTactile();

  const HandModel& model_;
  std::string source_;
  SimParams sim_;
  ObjectParams object_params_;
  ObjectBody object_body_;
  Eigen::Isometry3d palm_pose_;  // where the hand stands in the simulator's world
  PalmMotion palm_motion_;
  std::unique_ptr<PhysicsEngine> engine_;
  std::vector<double> targets_;
  std::vector<double> effort_;  // servo torques applied in the last step
  std::vector<TipState> tactile_;
  double time_ = 0.0;
  int64_t steps_ = 0;
  bool held_ = false;
};

// The object's mass properties from its shape (diagonal inertia about the centre, object frame).
Eigen::Vector3d ObjectInertia(const ObjectParams& object);


// Throws ConfigError naming `source` and the key: a mesh file that is missing, unreadable,
// empty, flat or not convex (a vertex inside its hull by more than 0.1 % of its size).
ObjectBody MakeObjectBody(const ObjectParams& object, const std::string& source);

}  // namespace dmpl
