"""The hand's links and their shapes from its URDF, and their poses for given joint angles
(forward kinematics), for drawing: the viewer reads the same file the simulator and the IK do.

Only what the hand's URDF uses is read: revolute, continuous and fixed joints; box, cylinder and
sphere geometry (visual, else collision) and mesh file names. Poses are 4x4 arrays in the frame of
the root link (the palm)."""
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np


class UrdfError(Exception):
    pass


def rpy_matrix(r, p, y):
    """R = Rz(y) Ry(p) Rx(r), the URDF convention."""
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def transform(xyz=(0, 0, 0), rpy=(0, 0, 0)):
    t = np.eye(4)
    t[:3, :3] = rpy_matrix(*rpy)
    t[:3, 3] = xyz
    return t


def axis_angle(axis, angle):
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    t = np.eye(4)
    t[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)
    return t


@dataclass
class Shape:
    kind: str                 # box, cylinder, sphere, mesh
    size: tuple               # box: (x, y, z); cylinder: (radius, length); sphere: (radius,)
    origin: np.ndarray        # 4x4 in the link frame
    mesh: str = ""


@dataclass
class Joint:
    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray


@dataclass
class Hand:
    root: str
    shapes: dict = field(default_factory=dict)   # link -> [Shape]
    joints: list = field(default_factory=list)   # parents before children

    def link_poses(self, angles):
        """{link: 4x4 pose in the root frame} for {joint name: angle}; a joint not given is 0."""
        poses = {self.root: np.eye(4)}
        for j in self.joints:
            t = poses[j.parent] @ j.origin
            if j.kind in ("revolute", "continuous"):
                t = t @ axis_angle(j.axis, angles.get(j.name, 0.0))
            poses[j.child] = t
        return poses


def _floats(text, n, what):
    try:
        v = tuple(float(x) for x in (text or "").split())
    except ValueError:
        v = ()
    if len(v) != n:
        raise UrdfError(f"{what}: expected {n} numbers, got '{text}'")
    return v


def _origin(el, what):
    o = el.find("origin") if el is not None else None
    if o is None:
        return np.eye(4)
    return transform(_floats(o.get("xyz", "0 0 0"), 3, what + " origin xyz"),
                     _floats(o.get("rpy", "0 0 0"), 3, what + " origin rpy"))


def _shape(el, what):
    g = el.find("geometry")
    if g is None or len(g) == 0:
        return None
    kind = g[0].tag
    origin = _origin(el, what)
    if kind == "box":
        return Shape("box", _floats(g[0].get("size"), 3, what + " box size"), origin)
    if kind == "cylinder":
        return Shape("cylinder", (float(g[0].get("radius")), float(g[0].get("length"))), origin)
    if kind == "sphere":
        return Shape("sphere", (float(g[0].get("radius")),), origin)
    if kind == "mesh":
        return Shape("mesh", _floats(g[0].get("scale", "1 1 1"), 3, what + " mesh scale"), origin,
                     g[0].get("filename", ""))
    return None


def load_hand(path):
    """Reads a URDF; raises UrdfError naming the file and what is wrong."""
    try:
        robot = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise UrdfError(f"{path}: {e}") from None
    hand = Hand(root="")
    try:
        for link in robot.findall("link"):
            name = link.get("name")
            shapes = [_shape(v, f"link {name}") for v in link.findall("visual")]
            if not any(shapes):
                shapes = [_shape(c, f"link {name}") for c in link.findall("collision")]
            hand.shapes[name] = [s for s in shapes if s is not None]
        joints = []
        for j in robot.findall("joint"):
            parent, child = j.find("parent"), j.find("child")
            if parent is None or child is None:
                raise UrdfError(f"joint {j.get('name')}: needs a parent and a child")
            axis = j.find("axis")
            joints.append(Joint(j.get("name"), j.get("type"), parent.get("link"), child.get("link"),
                                _origin(j, f"joint {j.get('name')}"),
                                np.array(_floats(axis.get("xyz"), 3, "axis") if axis is not None
                                         else (1.0, 0.0, 0.0))))
    except (TypeError, ValueError) as e:
        raise UrdfError(f"{path}: {e}") from None
    children = {j.child for j in joints}
    roots = [name for name in hand.shapes if name not in children]
    if len(roots) != 1:
        raise UrdfError(f"{path}: expected one root link, found {roots}")
    hand.root = roots[0]
    # Parents before children.
    known, pending = {hand.root}, joints
    while pending:
        ready = [j for j in pending if j.parent in known]
        if not ready:
            raise UrdfError(f"{path}: joints whose parent link is missing: "
                            f"{[j.name for j in pending]}")
        hand.joints += ready
        known |= {j.child for j in ready}
        pending = [j for j in pending if j not in ready]
    return hand
