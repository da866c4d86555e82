"""How much room the hand's grasp leaves an object in any orientation (issues 28 and 29).

For orientations drawn uniformly over SO(3) (seeded), the object held where a run held it when
its tasks began: can every finger put its tip on the object's surface within `deviation` rad
(seen from the object's centre) of where it stood then, with each of its links and the palm at
least `margin` off the object? This asks of the hand's geometry alone what the gait asks of it
(reorient_random.yaml keeps every finger within 0.35 rad of its home): the room any placement
has. The hand is the project's hand model (hand_geometry: forward kinematics, the links' shapes,
the joints' limits), each tip placed by damped least squares from the finger's posture then (one
posture of the finger's redundant joint, the IK's nearest: another might clear where this one
does not; --postures N also starts from N postures drawn within the joints' limits), its
links' surfaces sampled every 1.5 mm (a touch shallower than that between samples can go unseen).
The object's shape is the run's config: the simulator's truth, for an analysis of the hand, never
something the controller reads.

With --turn AXIS[:ANGLE] the orientations are not random but those the object passes through
as it turns ANGLE rad (default pi) about the palm's AXIS (x, y or z) from its orientation then:
at which angles of a full turn does some finger find no room? A gait that keeps every finger on
the object has to pass those angles with a finger that cannot be placed.

    tools/dmpl grasp-room RUN/run.lcmlog [--deviation 0.35] [--margin-mm 0] [--postures 0]
                          [--json FILE]
    tools/dmpl grasp-room RUN/run.lcmlog --turn y [--orientations 37]
"""
import argparse
import json
import sys
import tempfile
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from . import channels, experiment
from .hand_geometry import UrdfError, axis_angle, load_hand
from .logdata import Columns, LogData, LogError, extract
from .view import quat_matrix

SHAPES = ("sphere", "ellipsoid", "box", "cylinder", "capsule", "prism")
RING_DIRECTIONS = 8  # candidate directions on each of the two rings about a finger's home


class RoomError(Exception):
    pass


# --- The object: a signed distance (m, negative inside) in its own frame. -----------------

def object_sdf(obj):
    """A function of points [n, 3] (object frame) -> signed distances [n], for the run config's
    `object` section; RoomError for a shape it does not know."""
    shape = obj.get("shape", "sphere")
    if shape not in SHAPES:
        raise RoomError(f"object.shape '{shape}' is not supported (one of {', '.join(SHAPES)})")
    r = float(obj.get("radius", 0.025))
    half = float(obj.get("length", 0.09)) / 2.0
    if shape == "sphere":
        return lambda p: np.linalg.norm(p, axis=1) - r
    if shape == "ellipsoid":
        radii = np.asarray(obj.get("radii", [r, r, r]), dtype=float)
        # The scaled distance times the least radius: its sign is exact and its size at most
        # the true distance's (a margin asked of it is kept, or more).
        return lambda p: (np.linalg.norm(p / radii, axis=1) - 1.0) * radii.min()
    if shape == "box":
        h = np.asarray(obj.get("size", [0.05, 0.05, 0.05]), dtype=float) / 2.0
        return lambda p: _box_sdf(p, h)
    if shape == "cylinder":
        return lambda p: _extruded_sdf(np.linalg.norm(p[:, :2], axis=1) - r, np.abs(p[:, 2]) - half)
    if shape == "capsule":  # Bullet's: `length` is the cylindrical part, between two caps
        return lambda p: np.linalg.norm(
            p - np.c_[np.zeros((len(p), 2)), np.clip(p[:, 2], -half, half)], axis=1) - r
    sides = int(obj.get("sides", 6))
    # Corners at 2 pi k / n, of corner radius r (the simulator's): side k faces between two.
    a = (2 * np.arange(sides) + 1) * np.pi / sides
    normals, apothem = np.c_[np.cos(a), np.sin(a)], r * np.cos(np.pi / sides)
    return lambda p: _extruded_sdf((p[:, :2] @ normals.T).max(axis=1) - apothem,
                                   np.abs(p[:, 2]) - half)


def _box_sdf(p, h):
    q = np.abs(p) - h
    return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)


def _extruded_sdf(across, along):
    """A cross-section's distance `across` extruded by `along` (the distance beyond its ends)."""
    outside = np.hypot(np.maximum(across, 0.0), np.maximum(along, 0.0))
    return outside + np.minimum(np.maximum(across, along), 0.0)


def surface_along(sdf, direction):
    """(distance from the centre, outward unit normal) of the surface along `direction` (object
    frame) from the centre, for a convex object that contains its centre."""
    d = direction / np.linalg.norm(direction)
    lo, hi = 0.0, 0.5
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sdf(mid * d[None, :])[0] < 0 else (lo, mid)
    p = hi * d
    eps = 1e-5
    grad = np.array([(sdf((p + eps * e)[None, :]) - sdf((p - eps * e)[None, :]))[0]
                     for e in np.eye(3)])
    return hi, grad / np.linalg.norm(grad)


# --- The hand: one finger's chain, its links' surfaces, a tip placed by IK. ---------------

def _box_surface_points(size, spacing=0.0015):
    """Points on a box's six faces (its own frame), about `spacing` apart."""
    h = np.asarray(size, dtype=float) / 2.0
    out = []
    for axis in range(3):
        u, v = [k for k in range(3) if k != axis]
        nu, nv = (max(2, int(np.ceil(2 * h[k] / spacing)) + 1) for k in (u, v))
        gu, gv = np.meshgrid(np.linspace(-h[u], h[u], nu), np.linspace(-h[v], h[v], nv))
        for sign in (-1.0, 1.0):
            face = np.zeros((gu.size, 3))
            face[:, u], face[:, v], face[:, axis] = gu.ravel(), gv.ravel(), sign * h[axis]
            out.append(face)
    return np.vstack(out)


def _shape_points(shape):
    """Points on a link's collision shape (box, cylinder or sphere), in its link's frame."""
    if shape.kind == "box":
        local = _box_surface_points(shape.size)
    elif shape.kind == "cylinder":
        r, length = shape.size
        a, z = np.meshgrid(np.linspace(0, 2 * np.pi, 24, endpoint=False),
                           np.linspace(-length / 2, length / 2, max(2, int(length / 0.0015))))
        local = np.c_[r * np.cos(a.ravel()), r * np.sin(a.ravel()), z.ravel()]
    else:
        v = np.random.default_rng(0).normal(size=(300, 3))
        local = shape.size[0] * v / np.linalg.norm(v, axis=1)[:, None]
    return local @ shape.origin[:3, :3].T + shape.origin[:3, 3]


class FingerChain:
    """Finger `name`'s joints from the palm to its tip, its links' surface points (not the
    tip's: the tip is what touches) and a tip placed by damped least squares."""

    def __init__(self, hand, name):
        joints = {j.child: j for j in hand.joints}
        self.hand, self.name, self.chain, link = hand, name, [], name + "_tip"
        while link in joints:
            self.chain.insert(0, joints[link])
            link = joints[link].parent
        revolute = [j for j in self.chain if j.kind == "revolute"]
        unlimited = [j.name for j in revolute if j.limits is None]
        if unlimited or not revolute:
            raise RoomError(f"finger {name}: no joint limits for {unlimited or 'any joint'}")
        self.joints = [j.name for j in revolute]
        self.lower = np.array([j.limits[0] for j in revolute])
        self.upper = np.array([j.limits[1] for j in revolute])
        self.links = [(j.child, np.vstack([_shape_points(s) for s in hand.shapes[j.child]]))
                      for j in self.chain
                      if not j.child.endswith("_tip") and hand.shapes.get(j.child)]

    def poses(self, q):
        """{link: pose (palm frame)} of the chain's links at joints `q`."""
        return self.hand.link_poses(dict(zip(self.joints, q)), self.chain)

    def tip(self, q):
        return self.poses(q)[self.name + "_tip"][:3, 3]

    def place(self, q, target, iterations=60, tolerance=2e-4):
        """(joints, residual m) with the tip's centre at `target`, from `q`, within the limits."""
        q = np.clip(np.asarray(q, dtype=float), self.lower, self.upper)
        for _ in range(iterations):
            tip = self.tip(q)
            error = target - tip
            if np.linalg.norm(error) < tolerance:
                break
            jac = np.zeros((3, len(q)))
            for k in range(len(q)):
                dq = q.copy()
                dq[k] += 1e-6
                jac[:, k] = (self.tip(dq) - tip) / 1e-6
            step = jac.T @ np.linalg.solve(jac @ jac.T + 1e-6 * np.eye(3), error)
            q = np.clip(q + np.clip(step, -0.2, 0.2), self.lower, self.upper)
        return q, float(np.linalg.norm(target - self.tip(q)))

    def link_points(self, q):
        """{link: its surface points (palm frame)} at joints `q`."""
        poses = self.poses(q)
        return {link: pts @ poses[link][:3, :3].T + poses[link][:3, 3] for link, pts in self.links}


# --- The question. --------------------------------------------------------------------------

@dataclass
class Room:
    orientations: int = 0
    held: int = 0                                  # every finger found a placement
    palm_in_object: int = 0
    by_finger: dict = field(default_factory=dict)  # finger -> orientations it found one in
    # link -> orientations in which it, at its finger's home direction, comes within the margin
    at_home_blocked_by: dict = field(default_factory=dict)
    deviation_rad: float = 0.0
    margin_m: float = 0.0
    postures: int = 0                              # more starts of each placement
    # A turn's orientations (--turn): the angle of each, and who found no room there (fingers,
    # or "palm" where the palm lies in the object).
    angles_rad: list = field(default_factory=list)
    without_room: list = field(default_factory=list)


def random_rotation(rng):
    """A rotation matrix uniform over SO(3): a normalized Gaussian quaternion."""
    return quat_matrix(rng.normal(size=4))[:3, :3]


def candidate_directions(home, deviation):
    """`home` (unit) and rings at half and all of `deviation` rad about it."""
    out = [home]
    if deviation <= 0:
        return out
    other = np.array([1.0, 0, 0]) if abs(home[0]) < 0.9 else np.array([0, 1.0, 0])
    u = np.cross(home, other)
    u /= np.linalg.norm(u)
    for tilt in (deviation / 2, deviation):
        for k in range(RING_DIRECTIONS):
            about = axis_angle(home, 2 * np.pi * k / RING_DIRECTIONS)[:3, :3] @ u
            out.append(axis_angle(about, tilt)[:3, :3] @ home)
    return out


def turn_rotations(start, axis, angle, count):
    """(angles, rotations): `count` orientations evenly from `start` (3x3, object to palm) through
    a turn of `angle` rad about the palm's `axis`, both ends included."""
    angles = np.linspace(0.0, angle, count) if count > 1 else np.zeros(1)
    return list(angles), [axis_angle(axis, a)[:3, :3] @ start for a in angles]


def grasp_room(hand, joints, centre, obj, tip_radius, deviation=0.35, margin=0.0,
               orientations=200, seed=1, palm_points=None, rotations=None, postures=0):
    """Room for the object of config section `obj` held at `centre` (palm frame), the fingers at
    `joints` ({name: angle}) when it began: see the module's doc. `rotations` (object to palm,
    3x3 each; None: `orientations` random ones) are the orientations asked about. A placement is
    also tried from `postures` more starts, the finger's joints drawn within their limits (seeded):
    the finger's redundant joint gives a tip many postures, and the first found may touch where
    another clears."""
    sdf = object_sdf(obj)
    fingers = sorted({j.child[:-len("_tip")] for j in hand.joints if j.child.endswith("_tip")})
    chains = {f: FingerChain(hand, f) for f in fingers}
    home_q = {f: np.array([joints.get(n, 0.0) for n in chains[f].joints]) for f in fingers}
    home = {}
    for f in fingers:
        offset = chains[f].tip(home_q[f]) - centre
        home[f] = offset / np.linalg.norm(offset)
    if palm_points is None:
        palm_points = np.vstack([_shape_points(s) for s in hand.shapes.get(hand.root, [])] or
                                [np.zeros((0, 3))])
    if rotations is None:
        rng = np.random.default_rng(seed)
        rotations = [random_rotation(rng) for _ in range(orientations)]
    rng_postures = np.random.default_rng(seed + 1)
    starts = {f: [home_q[f]] + [rng_postures.uniform(chains[f].lower, chains[f].upper)
                                for _ in range(postures)] for f in fingers}
    room = Room(orientations=len(rotations), by_finger={f: 0 for f in fingers},
                deviation_rad=deviation, margin_m=margin, postures=postures)
    for rot in rotations:
        in_object = lambda pts: (pts - centre) @ rot  # noqa: E731  (palm -> object frame)
        if len(palm_points) and (sdf(in_object(palm_points)) < margin).any():
            room.palm_in_object += 1
            room.without_room.append(["palm"])
            continue
        every = True
        without = []
        for f in fingers:
            found = False
            for k, d in enumerate(candidate_directions(home[f], deviation)):
                along = rot.T @ d
                distance, normal = surface_along(sdf, along)
                target = centre + rot @ (distance * along / np.linalg.norm(along) +
                                         tip_radius * normal)
                for n, start in enumerate(starts[f]):
                    q, residual = chains[f].place(start, target)
                    if residual > 1e-3:
                        continue
                    blocking = [link for link, pts in chains[f].link_points(q).items()
                                if (sdf(in_object(pts)) < margin).any()]
                    if k == 0 and n == 0:  # the home direction, from the home posture
                        for link in blocking:
                            room.at_home_blocked_by[link] = (
                                room.at_home_blocked_by.get(link, 0) + 1)
                    if not blocking:
                        found = True
                        break
                if found:
                    break
            room.by_finger[f] += found
            every = every and found
            if not found:
                without.append(f)
        room.held += every
        room.without_room.append(without)
    return room


# --- From a recorded run. -------------------------------------------------------------------

def from_log(log, deviation, margin, orientations, seed, turn=None, postures=0):
    """The room of the run's home grasp (grasp_room); `turn` (axis, angle rad): along that turn
    from the object's orientation then, instead of random orientations."""
    log = Path(log)
    if not log.is_file():
        raise RoomError(f"no such log '{log}'")
    config_path = log.parent / "config.yaml"
    try:
        config = experiment.load_yaml(config_path)
        hand = load_hand(config_path)
    except (experiment.ExperimentError, UrdfError, OSError) as e:
        raise RoomError(f"the run's config '{config_path}': {e}") from None
    with tempfile.TemporaryDirectory(prefix="dmpl-room-") as tmp:
        try:
            extract(log, tmp)
        except LogError as e:
            raise RoomError(str(e)) from None
        data = LogData(Columns(tmp))
        truth = data.columns.table(channels.SENSORS_TRUE)
        if "joint_position" not in truth or "object_position" not in truth:
            raise RoomError(f"{log}: no simulator truth (recorded with --record none?)")
        names = data.columns.channels[channels.SENSORS_TRUE]["joints"]
        t = np.asarray(truth["utime"], dtype=float) / 1e6
        began = _tasks_began(data, log)
        i = min(int(np.searchsorted(t, began)), len(t) - 1)
        joints = dict(zip(names, np.asarray(truth["joint_position"][i], dtype=float)))
        centre = np.asarray(truth["object_position"][i], dtype=float)
        start = quat_matrix(np.asarray(truth["object_orientation"][i], dtype=float))[:3, :3]
    angles, rotations = [], None
    if turn is not None:
        angles, rotations = turn_rotations(start, turn[0], turn[1], orientations)
    tip = next((s.size[0] for link, shapes in hand.shapes.items() if link.endswith("_tip")
                for s in shapes if s.kind == "sphere"), 0.012)
    try:
        room = grasp_room(hand, joints, centre, config.get("object", {}) or {}, tip,
                          deviation, margin, orientations, seed, rotations=rotations,
                          postures=postures)
    except (TypeError, ValueError) as e:  # a value of the object section that is not a number
        raise RoomError(f"the run's object section in '{config_path}': {e}") from None
    room.angles_rad = [float(a) for a in angles]
    return room


def parse_turn(text):
    """(axis, angle) of --turn's AXIS[:ANGLE] (x, y or z; ANGLE rad, default pi)."""
    name, _, angle = text.partition(":")
    axes = {"x": (1.0, 0, 0), "y": (0, 1.0, 0), "z": (0, 0, 1.0)}
    if name not in axes:
        raise ValueError(f"--turn: the axis must be x, y or z, not '{name}'")
    try:
        value = float(angle) if angle else np.pi
    except ValueError:
        raise ValueError(f"--turn: the angle must be a number of radians, not '{angle}'") from None
    if not 0 < abs(value) <= 4 * np.pi:
        raise ValueError(f"--turn: the angle's size must lie in (0, 4 pi] rad, not {value}")
    return np.array(axes[name]), value


def spans(angles, flags):
    """The runs of consecutive angles where `flags` is true, as (first, last) pairs."""
    out = []
    for a, flag in zip(angles, flags):
        if flag and out and out[-1][2]:
            out[-1][1] = a
        elif flag:
            out.append([a, a, True])
        elif out:
            out[-1][2] = False
    return [(first, last) for first, last, _ in out]


def _tasks_began(data, log):
    """When the run's tasks began (the supervisor's first Tasks state): the home grasp."""
    sup = data.supervisor
    states = [str(s) for s in sup["grasp_state"]]
    if "Tasks" not in states:
        raise RoomError(f"{log}: the grasp never reached its tasks")
    return float(np.asarray(sup.t, dtype=float)[states.index("Tasks")])


def main(argv=None):
    p = argparse.ArgumentParser(prog="tools/dmpl grasp-room", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", help="a recorded run (full or analysis): its home grasp and object")
    p.add_argument("--deviation", type=float, default=0.35,
                   help="rad about each finger's home, seen from the centre (default 0.35)")
    p.add_argument("--margin-mm", type=float, default=0.0,
                   help="the least room between a link (or the palm) and the object")
    p.add_argument("--orientations", type=int, default=None,
                   help="how many (default 200 random ones; along a turn 37, 5 deg apart)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--turn", metavar="AXIS[:ANGLE]",
                   help="the orientations of a turn about the palm's x, y or z (ANGLE rad, "
                        "default pi) from the object's orientation then, not random ones")
    p.add_argument("--postures", type=int, default=0,
                   help="each placement also tried from this many more postures of the finger "
                        "(its joints drawn within their limits): room the run's posture misses")
    p.add_argument("--json", help="write the result here")
    a = p.parse_args(argv)
    if a.orientations is None:
        a.orientations = 37 if a.turn else 200
    if a.deviation < 0 or a.deviation > 1.5 or a.orientations < 1 or a.postures < 0:
        p.error("--deviation must lie in [0, 1.5], --orientations be at least 1 and --postures "
                "at least 0")
    try:
        turn = parse_turn(a.turn) if a.turn else None
    except ValueError as e:
        p.error(str(e))
    try:
        room = from_log(a.log, a.deviation, a.margin_mm / 1000.0, a.orientations, a.seed, turn,
                        a.postures)
    except RoomError as e:
        print(f"grasp-room: {e}", file=sys.stderr)
        return 2
    n = room.orientations
    print(f"{room.held} of {n} orientations ({100.0 * room.held / n:.0f} %) leave every finger a "
          f"tip placement within {room.deviation_rad:.2f} rad of its home with its links at "
          f"least {1000 * room.margin_m:.1f} mm off the object" +
          (f" (from the run's posture or {room.postures} more)" if room.postures else ""))
    print("per finger: " + ", ".join(f"{f} {k}" for f, k in room.by_finger.items()) +
          f"; the palm in the object: {room.palm_in_object}")
    blocked = sorted(room.at_home_blocked_by.items(), key=lambda item: -item[1])
    print("links in the way at the homes' directions (orientations): " +
          (", ".join(f"{link} {k}" for link, k in blocked) or "none"))
    if turn is not None:
        who = sorted({w for ws in room.without_room for w in ws})
        for w in who:
            runs = spans(room.angles_rad, [w in ws for ws in room.without_room])
            what = "the palm lies in the object" if w == "palm" else f"{w} has no room"
            print(f"{what} at " +
                  ", ".join(f"{first:.2f}" if first == last else f"{first:.2f}-{last:.2f}"
                            for first, last in runs) + " rad of the turn")
        if not who:
            print("every finger has room all along the turn")
    if a.json:
        try:
            Path(a.json).write_text(json.dumps(asdict(room), indent=1) + "\n")
        except OSError as e:
            print(f"grasp-room: cannot write '{a.json}': {e}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
