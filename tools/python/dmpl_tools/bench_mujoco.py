"""MuJoCo from PyPI as the reference of dmpl's MuJoCo engine in `tools/dmpl bench sim`: the same
URDF, scene, servo law and MuJoCo settings.

MuJoCo reads the hand's URDF itself; the sphere is added with a free joint. The scene is built in
the palm frame, with gravity turned into it (the palm faces up: world -z is palm -x), so nothing
needs the palm's pose. The contact and joint settings are those dmpl's engine reports it ran with
(`settings`, dmpl_bench_sim's "mujoco" object: cone, impratio, solref, solimp, joint damping,
solver iterations, the object's torsional and rolling friction and the contact dimension they
give). The joint torques are computed in Python each step from the same PD law, gains and effort
limits, and only `mj_step` is timed.
What differs: PyPI's MuJoCo is a newer release than Debian's 2.2.2, and dmpl also compensates the
links' gravity in its servos (a few dozen multiply-adds per step).
"""
import statistics
import time

import numpy as np

from .paths import ROOT

URDF = ROOT / "configs/hand/dmpl_hand.urdf"
FINGERS = ["T", "F", "M", "R"]


def _rotation_rpy(rpy):
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


def mujoco_step_us(scene, warmup, steps, settings):
    import mujoco
    sim, obj, player = scene.get("sim", {}), scene["object"], scene["joint_player"]
    phys = sim.get("physics", {})
    spec = mujoco.MjSpec.from_file(str(URDF))
    spec.option.timestep = phys.get("time_step", 0.001)
    palm = _rotation_rpy(sim.get("palm_rpy", [0.0, -np.pi / 2, 0.0]))
    spec.option.cone = (mujoco.mjtCone.mjCONE_ELLIPTIC if settings["cone"] == "elliptic"
                        else mujoco.mjtCone.mjCONE_PYRAMIDAL)
    spec.option.impratio = settings["impratio"]
    spec.option.iterations = settings["iterations"]
    spec.option.noslip_iterations = settings["noslip_iterations"]
    spec.option.gravity = (palm.T @ np.array([0.0, 0.0, -9.81])).tolist()
    # MuJoCo filters a body's contacts with its parent, but not when the parent is welded to the
    # world, as the palm is: the links mounted on the palm, and the thumb's second link (the
    # hand's one excluded pair, hand.self_collision_exclude), are excluded by name, as dmpl and
    # PyBullet exclude them.
    palm_body = spec.body("palm")
    for child in [*palm_body.bodies, spec.body("T_link1")]:
        spec.add_exclude(bodyname1="palm", bodyname2=child.name)
    for joint in spec.joints:  # MuJoCo 4 takes damping as polynomial coefficients
        joint.damping = [settings["joint_damping"], 0.0, 0.0]
    for geom in spec.geoms:
        geom.solref, geom.solimp = settings["solref"], settings["solimp"] + [0.5, 2.0]
    ball = spec.worldbody.add_body(name="object", pos=list(obj["position"]))
    ball.add_freejoint()
    ball.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[obj["radius"], 0, 0],
                  mass=obj["mass"], priority=1, condim=settings["condim"],
                  solref=settings["solref"],
                  solimp=settings["solimp"] + [0.5, 2.0],
                  friction=[obj.get("friction", 1.0), settings["torsional_friction"],
                            settings["rolling_friction"]])
    model = spec.compile()
    data = mujoco.MjData(model)
    names = [f"{f}_j{k}" for f in FINGERS for k in range(4)]
    qadr = np.array([model.joint(n).qposadr[0] for n in names])
    vadr = np.array([model.joint(n).dofadr[0] for n in names])
    data.qpos[qadr] = [a for f in FINGERS for a in sim["initial_joints"][f]]
    mujoco.mj_forward(model, data)
    target = np.array([a for f in FINGERS for a in player["waypoints"][0]["q"][f]])
    kp = np.tile(sim.get("servo", {}).get("kp", [2.0, 2.0, 1.5, 1.0]), 4)
    kd = np.tile(sim.get("servo", {}).get("kd", [0.03, 0.03, 0.02, 0.012]), 4)
    effort = np.tile([0.7, 0.7, 0.7, 0.35], 4)
    ball_id = model.body("object").id
    times, start = [], None
    for i in range(warmup + steps):
        tau = np.clip(kp * (target - data.qpos[qadr]) - kd * data.qvel[vadr], -effort, effort)
        data.qfrc_applied[vadr] = tau
        if i == warmup:
            start = data.xpos[ball_id].copy()
        t0 = time.perf_counter()
        mujoco.mj_step(model, data)
        if i >= warmup:
            times.append((time.perf_counter() - t0) * 1e6)
    touching = {model.geom_bodyid[c.geom1] if model.geom_bodyid[c.geom2] == ball_id
                else model.geom_bodyid[c.geom2]
                for c in data.contact[:data.ncon] if ball_id in
                (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2])}
    times.sort()
    return {"step_us_median": statistics.median(times), "step_us_p90": times[len(times) * 9 // 10],
            "steps": steps, "links_in_contact": len(touching),
            "object_moved_m": float(np.linalg.norm(data.xpos[ball_id] - start)),
            "engine": f"MuJoCo {mujoco.__version__}"}
