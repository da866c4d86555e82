"""The hand's links and their shapes, and their poses for given joint angles (forward
kinematics), for drawing. The description comes from the project's hand model (C++, urdfdom:
`dmpl_hand_geometry`), the one the simulator and the kinematics use: the viewer has no parser of
its own. Poses are 4x4 arrays in the frame of the root link (the palm)."""
import json
import subprocess
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


def axis_angle(axis, angle):
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    t = np.eye(4)
    t[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)
    return t


@dataclass
class Shape:
    kind: str                 # box, cylinder, sphere
    size: tuple               # box: (x, y, z); cylinder: (radius, length); sphere: (radius,)
    origin: np.ndarray        # 4x4 in the link frame


@dataclass
class Joint:
    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray
    limits: tuple = None      # (lower, upper) rad of a revolute joint with finite limits


@dataclass
class Hand:
    root: str
    shapes: dict = field(default_factory=dict)   # link -> [Shape]
    joints: list = field(default_factory=list)   # parents before children

    def link_poses(self, angles, joints=None):
        """{link: 4x4 pose in the root frame} for {joint name: angle}; a joint not given is 0.
        `joints` (default: all): the ones to follow, parents before children, the first one's
        parent the root (one finger's chain)."""
        poses = {self.root: np.eye(4)}
        for j in self.joints if joints is None else joints:
            t = poses[j.parent] @ j.origin
            if j.kind == "revolute":
                t = t @ axis_angle(j.axis, angles.get(j.name, 0.0))
            poses[j.child] = t
        return poses


def load_hand(config_path=None):
    """The hand of a dmpl config (its `hand` section; the defaults without one). Raises
    UrdfError with the hand model's own message."""
    from .paths import executable
    try:
        cmd = [executable("dmpl_hand_geometry"), "--config", str(config_path or "")]
    except FileNotFoundError as e:
        raise UrdfError(str(e)) from None
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    if done.returncode != 0:
        raise UrdfError(done.stderr.strip() or f"{cmd[0]} failed ({done.returncode})")
    doc = json.loads(done.stdout)
    pose = lambda values: np.array(values, dtype=float).reshape(4, 4)  # noqa: E731
    hand = Hand(root=doc["links"][0]["name"])
    for link in doc["links"]:
        hand.shapes[link["name"]] = [Shape(s["kind"], tuple(s["size"]), pose(s["origin"]))
                                     for s in link["shapes"]]
    for j in doc["joints"]:  # parents before children (the model's order)
        limits = (float(j["lower"]), float(j["upper"])) if "lower" in j else None
        hand.joints.append(Joint(j["name"], j["type"], j["parent"], j["child"], pose(j["origin"]),
                                 np.array(j["axis"], dtype=float), limits))
    return hand
