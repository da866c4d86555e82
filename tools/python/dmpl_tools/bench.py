"""tools/dmpl bench sim|ik|loop|faults [--json FILE]: benchmarks, measured side by side in one run.

sim:  median wall time of one physics step of the hand holding the paper's sphere
      (configs/bench/sim_hold.yaml), four engines side by side: dmpl's simulator with Bullet and
      with MuJoCo (sim.engine), PyBullet (PyPI) with the same time step, solver iterations and
      contact settings as dmpl-Bullet, and MuJoCo (PyPI) with dmpl-MuJoCo's settings
      (bench_mujoco.py). Keys: dmpl_step_us (Bullet), dmpl_mujoco_step_us, pybullet_step_us,
      mujoco_step_us, ratio (dmpl-Bullet / PyBullet), ratio_mujoco (dmpl-MuJoCo / MuJoCo),
      speedup_mujoco (dmpl-Bullet / dmpl-MuJoCo), and each engine's hold: the sphere's drift over
      the timed steps (3 s), *_moved_m.
faults: the rate at which each process of the loop, killed mid-gait, rejoins it (bench_faults.py).
"""
import argparse
import json
import math
import statistics
import subprocess
import sys
import time

import yaml

from .paths import ROOT, executable
from .bench_faults import NO_KILL, VICTIMS, bench_faults

SIM_SCENE = ROOT / "configs/bench/sim_hold.yaml"


def _rpy_quat(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (math.cos(r / 2), math.sin(r / 2), math.cos(p / 2), math.sin(p / 2),
                              math.cos(y / 2), math.sin(y / 2))
    return [sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy]  # x, y, z, w


def pybullet_step_us(scene, warmup, steps):
    """One PyBullet world built like dmpl's: same URDF, palm pose, joints, servo, object, solver."""
    import numpy as np
    import pybullet as p
    sim, obj, player = scene.get("sim", {}), scene["object"], scene["joint_player"]
    phys = sim.get("physics", {})
    client = p.connect(p.DIRECT)
    dt = phys.get("time_step", 0.001)
    p.setPhysicsEngineParameter(fixedTimeStep=dt, numSolverIterations=phys.get("solver_iterations", 50),
                                contactERP=0.08, frictionERP=0.2, contactSlop=1e-5,
                                warmStartingFactor=0.1, solverResidualThreshold=1e-7,
                                minimumSolverIslandSize=0, numSubSteps=0, physicsClientId=client)
    p.setGravity(0, 0, -9.81, physicsClientId=client)
    palm_orn = _rpy_quat(sim.get("palm_rpy", [0.0, -math.pi / 2, 0.0]))
    hand = p.loadURDF(str(ROOT / "configs/hand/dmpl_hand.urdf"), [0, 0, 0], palm_orn,
                      useFixedBase=True, physicsClientId=client,
                      flags=p.URDF_USE_SELF_COLLISION | p.URDF_USE_INERTIA_FROM_FILE)
    # PyBullet places a fixed base by its centre of mass: put the URDF palm frame at the origin.
    com_local = np.array([-0.0093, 0.0, -0.0475])
    rot = np.array(p.getMatrixFromQuaternion(palm_orn)).reshape(3, 3)
    p.resetBasePositionAndOrientation(hand, (rot @ com_local).tolist(), palm_orn,
                                      physicsClientId=client)
    joints = {}
    for j in range(p.getNumJoints(hand, physicsClientId=client)):
        info = p.getJointInfo(hand, j, physicsClientId=client)
        p.changeDynamics(hand, j, lateralFriction=1.0, rollingFriction=0.0, spinningFriction=0.0,
                         linearDamping=0.0, angularDamping=0.0, jointDamping=0.0,
                         physicsClientId=client)
        if info[2] == p.JOINT_REVOLUTE:
            joints[info[1].decode()] = j
    fingers = ["T", "F", "M", "R"]
    index = [joints[f"{f}_j{k}"] for f in fingers for k in range(4)]
    q0 = [a for f in fingers for a in sim["initial_joints"][f]]
    target = np.array([a for f in fingers for a in player["waypoints"][0]["q"][f]])
    for j, q in zip(index, q0):
        p.resetJointState(hand, j, q, physicsClientId=client)
    p.setJointMotorControlArray(hand, index, p.VELOCITY_CONTROL, forces=[0.0] * len(index),
                                physicsClientId=client)
    kp = np.tile(sim.get("servo", {}).get("kp", [2.0, 2.0, 1.5, 1.0]), 4)
    kd = np.tile(sim.get("servo", {}).get("kd", [0.03, 0.03, 0.02, 0.012]), 4)
    effort = np.tile([0.7, 0.7, 0.7, 0.35], 4)
    shape = p.createCollisionShape(p.GEOM_SPHERE, radius=obj["radius"], physicsClientId=client)
    pos = rot @ np.array(obj["position"])
    ball = p.createMultiBody(obj["mass"], shape, basePosition=pos.tolist(), physicsClientId=client)
    p.changeDynamics(ball, -1, lateralFriction=obj.get("friction", 1.0),
                     rollingFriction=obj.get("rolling_friction", 1e-4),
                     spinningFriction=obj.get("spinning_friction", 1e-3), linearDamping=0.0,
                     angularDamping=0.0, physicsClientId=client)
    times = []
    start = None
    for i in range(warmup + steps):
        states = p.getJointStates(hand, index, physicsClientId=client)
        q = np.array([s[0] for s in states])
        qd = np.array([s[1] for s in states])
        tau = np.clip(kp * (target - q) - kd * qd, -effort, effort)
        p.setJointMotorControlArray(hand, index, p.TORQUE_CONTROL, forces=tau.tolist(),
                                    physicsClientId=client)
        if i == warmup:
            start = np.array(p.getBasePositionAndOrientation(ball, physicsClientId=client)[0])
        t0 = time.perf_counter()
        p.stepSimulation(physicsClientId=client)
        if i >= warmup:
            times.append((time.perf_counter() - t0) * 1e6)
    end = np.array(p.getBasePositionAndOrientation(ball, physicsClientId=client)[0])
    contacts = len({c[3] for c in p.getContactPoints(hand, ball, physicsClientId=client)})
    p.disconnect(client)
    times.sort()
    return {"step_us_median": statistics.median(times), "step_us_p90": times[len(times) * 9 // 10],
            "steps": steps, "links_in_contact": contacts,
            "object_moved_m": float(np.linalg.norm(end - start))}


def dmpl_step_us(warmup, steps, engine):
    out = subprocess.run([executable("dmpl_bench_sim"), "--config", str(SIM_SCENE), "--engine",
                          engine, "--warmup", str(warmup), "--steps", str(steps)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def bench_sim(rounds=3, warmup=500, steps=3000):
    """Alternates the four engines `rounds` times; reports the median of the round medians."""
    with open(SIM_SCENE) as f:
        scene = yaml.safe_load(f)
    from .bench_mujoco import mujoco_step_us
    runs = {"dmpl": [], "dmpl_mujoco": [], "pybullet": [], "mujoco": []}
    for r in range(rounds):
        runs["dmpl"].append(dmpl_step_us(warmup, steps, "bullet"))
        runs["dmpl_mujoco"].append(dmpl_step_us(warmup, steps, "mujoco"))
        runs["pybullet"].append(pybullet_step_us(scene, warmup, steps))
        runs["mujoco"].append(mujoco_step_us(scene, warmup, steps,
                                             runs["dmpl_mujoco"][-1]["mujoco"]))
        print(f"round {r + 1}/{rounds}: "
              + ", ".join(f"{label} {runs[key][-1]['step_us_median']:.1f} us"
                          for key, label in (("dmpl", "dmpl-Bullet"), ("dmpl_mujoco", "dmpl-MuJoCo"),
                                             ("pybullet", "PyBullet"), ("mujoco", "MuJoCo"))),
              file=sys.stderr)
    us = {key: statistics.median(x["step_us_median"] for x in v) for key, v in runs.items()}
    return {"dmpl_step_us": us["dmpl"], "dmpl_mujoco_step_us": us["dmpl_mujoco"],
            "pybullet_step_us": us["pybullet"], "mujoco_step_us": us["mujoco"],
            "ratio": us["dmpl"] / us["pybullet"],
            "ratio_mujoco": us["dmpl_mujoco"] / us["mujoco"],
            "speedup_mujoco": us["dmpl"] / us["dmpl_mujoco"],
            **{f"{key}_moved_m": statistics.median(x["object_moved_m"] for x in v)
               for key, v in runs.items()},
            "rounds": rounds, "steps_per_round": steps,
            **{key: v[-1] for key, v in runs.items()}}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl bench", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["sim", "ik", "loop", "faults"])
    ap.add_argument("--json", help="write the result here too")
    ap.add_argument("--rounds", type=int, help="alternating rounds (default: sim 3, loop 5)")
    ap.add_argument("--kills", type=int, default=20, help="faults: kills per process (20)")
    ap.add_argument("--lockstep", action="store_true", help="faults: in lockstep (default: real time)")
    ap.add_argument("--processes", default=",".join(VICTIMS + (NO_KILL,)),
                    help="faults: the processes to kill, in turn; none: a run without a kill, "
                         "the baseline (default: %(default)s)")
    ap.add_argument("--keep-failed", metavar="DIR",
                    help="faults: record every trial and keep those that did not rejoin in DIR")
    args = ap.parse_args(argv)
    from .lcm_url import LcmUnavailable
    from .process_set import SetError
    try:
        if args.what == "sim":
            result = bench_sim(args.rounds or 3)
        elif args.what == "ik":
            from .bench_ik import bench_ik
            result = bench_ik()
        elif args.what == "loop":
            from .bench_loop import bench_loop
            result = bench_loop(args.rounds or 5)
        else:
            victims = [p for p in args.processes.split(",") if p]
            unknown = sorted(set(victims) - set(VICTIMS + (NO_KILL,)))
            if unknown or args.kills < 1:
                ap.error(f"--processes takes {', '.join(VICTIMS + (NO_KILL,))}; --kills at least 1"
                         + (f" (unknown: {', '.join(unknown)})" if unknown else ""))
            result = bench_faults(args.kills, args.lockstep, keep_failed=args.keep_failed,
                                  victims=victims, progress=lambda t: print(t, file=sys.stderr))
    except SetError as e:  # e.g. another run on the URL the loop benchmark needs
        print(f"dmpl bench: error: {e}", file=sys.stderr)
        return 2
    except LcmUnavailable as e:
        print(f"dmpl bench: error: {e}", file=sys.stderr)
        return 3
    text = json.dumps(result, indent=2)
    print(text)
    if args.json:
        try:
            with open(args.json, "w") as f:
                f.write(text + "\n")
        except OSError as e:
            print(f"dmpl bench: error: cannot write {args.json}: {e.strerror}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
