#pragma once
#include <array>
#include <map>
#include <string>
#include <vector>

#include "components/runtime/params.h"
#include "sim_process/sim/palm_motion.h"

namespace dmpl {

// The physics settings PyBullet uses for grasping, not Bullet's game defaults.
struct PhysicsParams {
  double time_step = 0.001;           // s
  int solver_iterations = 50;
  double contact_erp = 0.08;          // erp2
  double friction_erp = 0.2;
  double linear_slop = 1e-5;
  int minimum_solver_batch_size = 0;
  double warmstarting_factor = 0.1;
  double residual_threshold = 1e-7;
  double collision_margin = 0.0005;   // m; Bullet's 0.04 default is larger than a fingertip
  bool self_collision = true;         // hand links collide with each other, except parent/child
  std::array<double, 3> gravity = {0.0, 0.0, -9.81};  // world frame

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(time_step), AboveUpTo(0, 0.01));
    a->Visit(DMPL_NVP(solver_iterations), AtLeast(1));
    a->Visit(DMPL_NVP(contact_erp), InRange(0, 1));
    a->Visit(DMPL_NVP(friction_erp), InRange(0, 1));
    a->Visit(DMPL_NVP(linear_slop));
    a->Visit(DMPL_NVP(minimum_solver_batch_size));
    a->Visit(DMPL_NVP(warmstarting_factor));
    a->Visit(DMPL_NVP(residual_threshold));
    a->Visit(DMPL_NVP(collision_margin), InRange(0, 0.005));
    a->Visit(DMPL_NVP(self_collision));
    a->Visit(DMPL_NVP(gravity));
  }
};

// A joint position servo of bounded stiffness, like a real hand's: tau = kp (q* - q) - kd qd
// (+ gravity compensation of the links), clamped to the URDF effort limit. A blocked finger then
// presses with a force set by its stiffness and error, not by its torque limit. Gains are given
// per position in a finger's chain (base joint first) and apply to every finger.
struct ServoParams {
  std::vector<double> kp = {2.0, 2.0, 1.5, 1.0};       // N*m/rad
  std::vector<double> kd = {0.03, 0.03, 0.02, 0.012};  // N*m*s/rad
  std::map<std::string, double> finger_scale;          // finger -> factor on its kp and kd
  bool gravity_compensation = true;

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(kp), AtLeast(0));
    a->Visit(DMPL_NVP(kd), AtLeast(0));
    a->Visit(DMPL_NVP(finger_scale), AboveUpTo(0, 10));
    a->Visit(DMPL_NVP(gravity_compensation));
  }
};

struct TactileParams {
  double contact_threshold_n = 0.01;  // a fingertip is in contact above this normal force
  double finger_friction = 1.0;       // Bullet multiplies it with the object's friction

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(contact_threshold_n), AtLeast(0));
    a->Visit(DMPL_NVP(finger_friction), AtLeast(0));
  }
};

// Section `sim.mujoco`: what only the MuJoCo engine reads (sim.engine: mujoco). The shared
// physics (time step, gravity, friction, servos) stays in `physics`, `servo` and `object`.
// The integrator is MuJoCo's semi-implicit Euler, as Bullet's: a step is split in two halves
// (mj_step1, mj_step2) so that the servos' gravity compensation reads the step's own kinematics.
struct MujocoParams {
  // Joint damping MuJoCo integrates implicitly, N*m*s/rad, on top of the servo's kd: explicit
  // damping alone lets 1 ms servos on 10-60 g links ring.
  double joint_damping = 0.03;
  // Friction: an elliptic cone, frictional constraints 300 times as stiff as normal ones, and
  // contacts that yield less than MuJoCo's default (solimp). Its soft contacts let a grasp creep:
  // with the pyramidal cone and impratio 1 the sphere crept out of tools/dmpl bench sim's grasp
  // in 4 s; at impratio 30 and solimp's defaults it moved 0.38 mm in 3 s; with these, 0.009 mm
  // (0.07 mm while the contacts also resisted spin and roll). Stiffer still (solimp 0.99/0.999)
  // the gait lost its contacts (about y 0 of 4 seeds).
  std::string cone = "elliptic";      // pyramidal or elliptic
  // Which pairs of geoms are tested for contact each step. `dynamic`: MuJoCo's broad phase
  // (bounding boxes of every body, sorted along their principal axis) finds them; `predefined`:
  // the compiler lists once every pair the broad phase could pass (what its filters allow:
  // contype/conaffinity, welded bodies, parents, exclusions), with the contact parameters the
  // dynamic pairs would get, and each step tests them by their bounding spheres only. The same
  // contacts in the same order, so the same run bit for bit; in a hand of 21 bodies a faster
  // step (docs/benchmarks.md).
  std::string collision = "predefined";  // dynamic or predefined
  int iterations = 100;               // constraint solver (Newton)
  int noslip_iterations = 0;
  double impratio = 300.0;            // frictional-to-normal impedance ratio
  // Contact stiffness: time constant (s), damping ratio. At 2 ms (two steps, the stiffest MuJoCo
  // allows) an explorer pressing 0.1 N bounced off the sphere and came back by a guarded move:
  // turns 15-30 % slower than Bullet's, random goals a median of 92.5 (100 in 5 of 10 runs).
  // From 3 to 10 ms the turns are Bullet's; 100 goals in 9, 10, 9 and 6 runs of 10 at 3, 4, 5
  // and 10 ms. Softer contacts sink further under a hard press (a saturated finger advances
  // 0.1 rad further than in Bullet in 1 s).
  std::array<double, 2> solref = {0.004, 1.0};
  // Contact impedance (dmin, dmax, width m): how little a contact yields (d near 1: stiff); a
  // held object's creep grows with (1 - d) / d.
  std::array<double, 3> solimp = {0.95, 0.99, 0.001};
  // The object's spin and roll resistance at a contact, m; 0 leaves the component out of the
  // contact. Bullet's finger contacts have neither (it multiplies the two bodies' coefficients,
  // and the links' are 0). In the elliptic cone every component shares the one cone: a spin
  // resistance of 5 mm took so much of it that a sphere of friction 0.4 slipped out of the gait
  // (0 of 3 seeds; 3 of 3 without it).
  double torsional_friction = 0.0;
  double rolling_friction = 0.0;

  // Which components of friction the object's contacts carry (MuJoCo's condim): sliding (3),
  // and spin (4) and roll (6) when their coefficients are not zero.
  int contact_dimension() const {
    if (rolling_friction > 0) return 6;
    return torsional_friction > 0 ? 4 : 3;
  }

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(joint_damping), AtLeast(0));
    a->Visit(DMPL_NVP(cone));
    a->Visit(DMPL_NVP(collision));
    a->Visit(DMPL_NVP(iterations), AtLeast(1));
    a->Visit(DMPL_NVP(noslip_iterations), AtLeast(0));
    a->Visit(DMPL_NVP(impratio), AtLeast(1));
    a->Visit(DMPL_NVP(solref));
    a->Visit(DMPL_NVP(solimp));
    a->Visit(DMPL_NVP(torsional_friction), AtLeast(0));
    a->Visit(DMPL_NVP(rolling_friction), AtLeast(0));
  }
};

// Section `sim`.
struct SimParams {
  // The physics engine: bullet (the default, the one the project's results are tuned on) or
  // mujoco (a second contact model, several times faster).
  std::string engine = "bullet";
  PhysicsParams physics;
  MujocoParams mujoco;
  ServoParams servo;
  TactileParams tactile;
  std::array<double, 3> palm_position = {0.0, 0.0, 0.0};  // world, m
  std::array<double, 3> palm_rpy = {0.0, -1.5707963267948966, 0.0};  // palm up: palm x -> world z
  PalmMotionParams palm_motion;  // how the palm turns while the task runs (palm_motion.h)
  std::map<std::string, std::vector<double>> initial_joints;  // finger -> joint angles (rad)
  int steps_per_tick = 1;
  // The actuation delay: the step from tick k applies the joint command that answered tick
  // k - command_delay_ticks (a sim control sent in answer to tick s acts before the step from
  // s + 1 + delay). 1, as a real hand's servos act on a command one cycle after the sensing it
  // answers; it also lets the simulator step while the nodes compute the next command, so a
  // lockstep loop on two CPUs runs in parallel. 0: the command of tick k drives the step from k.
  int command_delay_ticks = 1;
  // One process in lockstep with that delay, allowed two CPUs or more: the step runs on a thread
  // of its own while the other nodes answer the tick before (background_step.h); the same run,
  // bit for bit.
  bool background_step = true;
  double duration_s = 10.0;        // the run ends after this much simulated time
  double realtime_rate = 1.0;      // real-time mode: sim seconds per wall second
  std::string stats_file;          // at the end: JSON with ticks, real-time factor, latencies

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(engine));
    a->Visit(DMPL_NVP(physics));
    a->Visit(DMPL_NVP(mujoco));
    a->Visit(DMPL_NVP(servo));
    a->Visit(DMPL_NVP(tactile));
    a->Visit(DMPL_NVP(palm_position));
    a->Visit(DMPL_NVP(palm_rpy));
    a->Visit(DMPL_NVP(palm_motion));
    a->Visit(DMPL_NVP(initial_joints));
    a->Visit(DMPL_NVP(steps_per_tick), AtLeast(1));
    a->Visit(DMPL_NVP(command_delay_ticks), InRange(0, 100));
    a->Visit(DMPL_NVP(background_step));
    a->Visit(DMPL_NVP(duration_s), Above(0));
    a->Visit(DMPL_NVP(realtime_rate), Above(0));
    a->Visit(DMPL_NVP(stats_file));
  }
  void Validate(const std::string& source) const;
};

// Section `object`: for the simulator only; no controller ever reads it.
struct ObjectParams {
  std::string shape = "sphere";        // sphere, cylinder, box, capsule, ellipsoid, prism, mesh
  double radius = 0.025;               // sphere, cylinder, capsule; prism: its corners'
  double length = 0.09;                // cylinder, capsule, prism (along the object's z)
  int sides = 6;                       // prism: a regular polygon of this many sides
  // mesh: an OBJ or STL file (relative paths from $DMPL_ROOT), its convex hull, its vertices
  // scaled by `scale` (a file in millimetres: 0.001); its pose is the file's frame.
  std::string mesh;
  double scale = 1.0;
  std::array<double, 3> size = {0.05, 0.05, 0.05};     // box edge lengths
  std::array<double, 3> radii = {0.03, 0.025, 0.025};  // ellipsoid semi-axes
  double mass = 0.05;                  // kg; inertia follows from the shape
  double friction = 1.0;
  double rolling_friction = 1e-4;      // > 0, or Bullet ignores spinning friction
  double spinning_friction = 1e-3;
  double restitution = 0.0;
  std::array<double, 3> position = {0.085, 0.0, 0.025};  // palm frame, m
  std::array<double, 3> rpy = {0.0, 0.0, 0.0};           // palm frame
  bool held = true;                    // starts fixed in space, "held by a person"

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(shape));
    a->Visit(DMPL_NVP(radius));
    a->Visit(DMPL_NVP(length));
    a->Visit(DMPL_NVP(sides), InRange(3, 64));
    a->Visit(DMPL_NVP(mesh));
    a->Visit(DMPL_NVP(scale), Above(0));
    a->Visit(DMPL_NVP(size));
    a->Visit(DMPL_NVP(radii));
    a->Visit(DMPL_NVP(mass), Above(0));
    a->Visit(DMPL_NVP(friction), AtLeast(0));
    a->Visit(DMPL_NVP(rolling_friction), AtLeast(0));
    a->Visit(DMPL_NVP(spinning_friction), AtLeast(0));
    a->Visit(DMPL_NVP(restitution), InRange(0, 1));
    a->Visit(DMPL_NVP(position));
    a->Visit(DMPL_NVP(rpy));
    a->Visit(DMPL_NVP(held));
  }
  void Validate(const std::string& source) const;
};

}  // namespace dmpl
