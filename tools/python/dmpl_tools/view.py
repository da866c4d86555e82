"""tools/dmpl view: the hand, the object and the contacts in 3-D in the browser (Meshcat).

  tools/dmpl view [--lcm-url URL]       live: listens to a running set and prints the URL to open
  tools/dmpl view LOG                   plays a recorded run: Animations panel (play, pause, scrub
                                        the time, speed = timeScale) in the page it prints
  tools/dmpl view LOG --html FILE       writes one self-contained HTML replay that opens offline

Shown: the hand's links (from the project's hand model), the object (shape and size from the run's config,
for display only), each fingertip contact as a point with an arrow along its normal scaled by its
force (2 cm per N, into the translucent object), each fingertip coloured by its role (blue grip, orange explore, grey free),
the sensed (noisy) object pose as a translucent ghost beside the true one, the target
orientation (task) or the current goal orientation (goals) as a frame, the fingertip targets as
small cubes (live: the points the supervisor sends them to), a red ball at a finger's distal
joint while the object presses on its links rather than its tip (the simulator's truth), an arrow
along gravity from the palm's origin (the palm's IMU, truth), the whole hand turned as the palm
turns (sim.palm_motion: the least rotation that takes the palm's first gravity to its gravity
now), and a text: sim time, grasp and regrasp state, rotation so far (or goals reached).

The live view only listens, to the truth and sensed channels the simulator and the noise injector
send for viewers at run.view_rate_hz (30 Hz) and the supervisor's status and task: it keeps the
latest message of each (no decoding on arrival), draws at most `--fps` (15) frames a second from
the latest, sends only the transforms that changed, and runs under SCHED_IDLE: a slow browser
drops frames, and the loop's processes always run first. Meshcat (PyPI `meshcat`) serves its viewer locally; nothing is fetched from
the internet."""
import argparse
import contextlib
import html
import io
import json
import os
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from . import channels, experiment
from .hand_geometry import UrdfError, load_hand, rpy_matrix
from .lcm_url import LcmUnavailable, resolve_lcm_url
from .logdata import (ROLE_NAMES, Columns, LogData, LogError, cumulative_rotation, extract,
                      task_axis)
from .paths import ROOT

ROLE_COLOURS = {0: 0x9e9e9e, 1: 0x1f77b4, 2: 0xff9800}  # free, grip, explore
ARROW_M_PER_N = 0.02
GRAVITY_ARROW_M = 0.05
FIELDS = {
    channels.SENSORS_TRUE: ["utime", "seq", "object_position", "object_orientation",
                            "joint_position", "tactile_force", "tactile_in_contact",
                            "tactile_position", "tactile_normal", "tactile_link_force",
                            "gravity"],
    channels.SENSORS: ["utime", "seq", "object_position", "object_orientation"],
    channels.SUPERVISOR_STATUS: None, channels.TASK: None,
    channels.CONTROLLER_REPORT: ["utime", "seq", "target_position"],
    channels.CONTROLLER_STATUS: ["utime", "seq", "target_position"],
}


class ViewError(Exception):
    pass


def open_visualizer():
    """A Meshcat visualizer with its own local server (quietly: we print the URL ourselves)."""
    meshcat, _ = _meshcat()
    with contextlib.redirect_stdout(io.StringIO()):
        return meshcat.Visualizer()


def close_visualizer(vis):
    """Ends the visualizer's server and its socket (Meshcat itself only does it at exit)."""
    window = vis.window
    if getattr(window, "server_proc", None) is not None:
        window.server_proc.kill()
        window.server_proc.wait()
    window.zmq_socket.close(linger=0)


def _meshcat():
    try:
        import warnings
        warnings.filterwarnings("ignore", category=DeprecationWarning, module="meshcat")
        warnings.filterwarnings("ignore", message=".*zmq.eventloop.ioloop.*")
        import meshcat
        import meshcat.geometry as g
    except ImportError:
        raise ViewError("the Python package 'meshcat' is missing: run tools/dmpl view (it installs "
                        "what is missing) or tools/dmpl setup") from None
    return meshcat, g


def quat_matrix(q):
    """4x4 rotation of a [w, x, y, z] quaternion."""
    w, x, y, z = q / max(np.linalg.norm(q), 1e-12)
    t = np.eye(4)
    t[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                 [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                 [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return t


def pose_matrix(position, q):
    t = quat_matrix(np.asarray(q, dtype=float))
    t[:3, 3] = position
    return t


def prism_mesh(sides, radius, length):
    """A regular prism as the simulator builds it (along z, a corner on +x): vertices, faces."""
    angles = 2 * np.pi * np.arange(sides) / sides
    ring = np.stack([radius * np.cos(angles), radius * np.sin(angles)], axis=1)
    vertices = np.vstack([np.c_[ring, np.full(sides, -length / 2)],
                          np.c_[ring, np.full(sides, length / 2)]])
    faces = []
    for k in range(sides):
        j = (k + 1) % sides
        faces += [[k, j, sides + j], [k, sides + j, sides + k]]
        if 0 < k < sides - 1:
            faces += [[0, k + 1, k], [sides, sides + k, sides + k + 1]]
    return vertices, np.array(faces)


def rotation_between(a, b):
    """The least rotation (3 x 3) that turns direction `a` into direction `b`."""
    a = np.asarray(a, dtype=float) / np.linalg.norm(a)
    b = np.asarray(b, dtype=float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    s, c = np.linalg.norm(axis), float(np.dot(a, b))
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        # Opposite: half a turn about any axis across them.
        other = np.cross(a, [1.0, 0.0, 0.0])
        other = other if np.linalg.norm(other) > 1e-6 else np.cross(a, [0.0, 1.0, 0.0])
        k = other / np.linalg.norm(other)
        return 2.0 * np.outer(k, k) - np.eye(3)
    k = axis / s
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * kx + (1 - c) * kx @ kx


def arrow_matrix(start, direction, length):
    """A unit cylinder (Meshcat: along y, centred) stretched from `start` along `direction`."""
    d = np.asarray(direction, dtype=float)
    n = np.linalg.norm(d)
    t = np.eye(4)
    if n < 1e-9 or length < 1e-6:
        return HIDDEN
    y = d / n
    x = np.cross(y, [0.0, 0.0, 1.0])
    if np.linalg.norm(x) < 1e-6:
        x = np.cross(y, [1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    z = np.cross(x, y)
    t[:3, 0], t[:3, 1], t[:3, 2] = x, y * length, z
    t[:3, 3] = np.asarray(start) + y * length / 2
    return t


class Scene:
    """The objects of the view under one root: built once, then posed frame by frame."""

    def __init__(self, vis, config, config_path=None):
        """`config`: the run's config (a dict); `config_path`: its file, whose hand the project's
        hand model reads (the defaults without one)."""
        self.meshcat, self.g = _meshcat()
        self.vis = vis
        self.config = config
        hand_cfg = config.get("hand", {})
        try:
            self.hand = load_hand(config_path)
        except UrdfError as e:
            raise ViewError(str(e)) from None
        self.fingers = [f["name"] for f in hand_cfg.get("fingers", [])] or ["T", "F", "M", "R"]
        # Each finger's distal link (the tip's parent): where a link touch is shown.
        parents = {j.child: j.parent for j in self.hand.joints}
        self.distal_links = {f: parents.get(f + "_tip") for f in self.fingers}
        # The truth force on a finger's links that counts as a touch: the metrics' threshold.
        self.link_touch_n = config.get("metrics", {}).get(
            "link_contact_n", experiment.METRICS_DEFAULTS["link_contact_n"])
        sim = config.get("sim", {})
        self.palm = np.eye(4)
        self.palm[:3, :3] = rpy_matrix(*sim.get("palm_rpy", [0.0, -np.pi / 2, 0.0]))
        self.palm[:3, 3] = sim.get("palm_position", [0.0, 0.0, 0.0])
        self.first_gravity = None  # the palm's gravity in the first frame drawn
        # Bullet's cylinders and capsules lie along z, Meshcat's along y.
        self.object_fix = np.eye(4)
        obj = config.get("object", {})
        if obj.get("shape", "sphere") in ("cylinder", "capsule"):
            self.object_fix[:3, :3] = rpy_matrix(np.pi / 2, 0, 0)
        if obj.get("shape") == "mesh":  # the file's units: object.scale
            self.object_fix[:3, :3] *= float(obj.get("scale", 1.0))
        self._build()

    def _build(self):
        g = self.g
        # A camera near the hand (the default one frames metres); the 20 m grid hidden.
        self.vis["/Cameras/default/rotated/<object>"].set_property("position", [0.16, 0.14, 0.16])
        self.vis["/Cameras/default"].set_transform(_at([0.0, 0.0, 0.07]))
        self.vis["/Grid"].set_property("visible", False)
        self.vis["/Axes"].set_property("visible", False)
        root = self.vis["dmpl"]
        root.delete()
        root.set_transform(self.palm)
        hand = root["hand"]
        for link, shapes in self.hand.shapes.items():
            for i, s in enumerate(shapes):
                geom = self._geometry(s)
                if geom is None:
                    continue
                node = hand[link][str(i)]
                node.set_object(geom, g.MeshLambertMaterial(color=0xd7ccc8))
                node.set_transform(s.origin @ self._shape_fix(s))
        obj = self._object_geometry()
        root["object"]["true"].set_object(
            obj, g.MeshLambertMaterial(color=0xc62828, opacity=0.75, transparent=True))
        root["object"]["sensed"].set_object(
            obj, g.MeshLambertMaterial(color=0x42a5f5, opacity=0.3, transparent=True))
        root["object"]["true_axes"].set_object(g.triad(0.04))
        root["goal"].set_object(g.triad(0.06))
        for f in self.fingers:
            for role, colour in ROLE_COLOURS.items():
                root["tips"][f][ROLE_NAMES[role]].set_object(
                    g.Sphere(0.0125), g.MeshLambertMaterial(color=colour, opacity=0.6,
                                                            transparent=True))
            root["contacts"][f]["point"].set_object(g.Sphere(0.002),
                                                    g.MeshLambertMaterial(color=0x000000))
            root["contacts"][f]["arrow"].set_object(g.Cylinder(1.0, 0.0015),
                                                    g.MeshLambertMaterial(color=0x2e7d32))
            root["targets"][f].set_object(g.Box([0.004] * 3),
                                          g.MeshLambertMaterial(color=0x6a1b9a))
            # Shown while the object presses on the finger's links (not its tip): truth.
            root["link_touch"][f].set_object(g.Sphere(0.008), g.MeshLambertMaterial(
                color=0xff1744, opacity=0.7, transparent=True))
        root["gravity"].set_object(g.Cylinder(1.0, 0.002), g.MeshLambertMaterial(color=0x000000))

    def _geometry(self, s):
        g = self.g
        if s.kind == "box":
            return g.Box(list(s.size))
        if s.kind == "sphere":
            return g.Sphere(s.size[0])
        if s.kind == "cylinder":
            return g.Cylinder(s.size[1], s.size[0])
        return None  # meshes: the hand's URDF has none

    @staticmethod
    def _shape_fix(s):
        """URDF cylinders lie along z, Meshcat's along y."""
        t = np.eye(4)
        if s.kind == "cylinder":
            t[:3, :3] = rpy_matrix(np.pi / 2, 0, 0)
        return t

    def _object_geometry(self):
        g = self.g
        o = self.config.get("object", {})
        shape, r = o.get("shape", "sphere"), float(o.get("radius", 0.025))
        if shape == "cylinder":
            return g.Cylinder(float(o.get("length", 0.09)), r)
        if shape == "box":
            return g.Box(list(o.get("size", [0.05, 0.05, 0.05])))
        if shape == "ellipsoid":
            return g.Ellipsoid(list(o.get("radii", [r, r, r])))
        if shape == "capsule":
            return g.Cylinder(float(o.get("length", 0.06)) + 2 * r, r)  # close enough to see
        if shape == "prism":
            vertices, faces = prism_mesh(int(o.get("sides", 6)), r, float(o.get("length", 0.09)))
            return g.TriangularMeshGeometry(vertices, faces)
        if shape == "mesh":
            path = Path(o.get("mesh", ""))
            path = path if path.is_absolute() else ROOT / path
            if not path.is_file():
                raise ViewError(f"object.mesh: no such mesh file '{path}'")
            reader = g.StlMeshGeometry if path.suffix.lower() == ".stl" else g.ObjMeshGeometry
            return reader.from_file(str(path))
        return g.Sphere(r)

    def draw(self, node, frame):
        """Poses every object for one frame; `node` is the live visualizer or an animation
        frame of it (both take set_transform and set_property)."""
        root = node["dmpl"]
        gravity = frame.get("gravity")
        if gravity is not None and np.all(np.isfinite(gravity)) and np.linalg.norm(gravity) > 0:
            if self.first_gravity is None:
                self.first_gravity = np.array(gravity, dtype=float)
            # The palm in the world now: its gravity turned back to where it first was.
            palm = self.palm.copy()
            palm[:3, :3] = self.palm[:3, :3] @ rotation_between(gravity, self.first_gravity)
            root.set_transform(palm)
            root["gravity"].set_transform(arrow_matrix(np.zeros(3), gravity, GRAVITY_ARROW_M))
        poses = self.hand.link_poses(frame["joints"])
        for link, shapes in self.hand.shapes.items():
            if link in poses:
                root["hand"][link].set_transform(poses[link])
        fix = self.object_fix
        true_pose = pose_matrix(frame["object_position"], frame["object_orientation"])
        root["object"]["true"].set_transform(true_pose @ fix)
        root["object"]["true_axes"].set_transform(true_pose)
        if frame.get("sensed_position") is not None:
            root["object"]["sensed"].set_transform(
                pose_matrix(frame["sensed_position"], frame["sensed_orientation"]) @ fix)
        goal = frame.get("goal")
        root["goal"].set_transform(pose_matrix(frame["object_position"], goal)
                                   if goal is not None else HIDDEN)
        for k, f in enumerate(self.fingers):
            tip = poses.get(f + "_tip", np.eye(4))
            role = frame["roles"][k]
            for r, name in ROLE_NAMES.items():
                root["tips"][f][name].set_transform(tip if r == role else HIDDEN)
            force = frame["force"][k]
            if frame["in_contact"][k]:
                p = frame["contact_position"][k]
                root["contacts"][f]["point"].set_transform(_at(p))
                # The force on the object: against the normal (object -> fingertip).
                root["contacts"][f]["arrow"].set_transform(
                    arrow_matrix(p, -frame["contact_normal"][k], force * ARROW_M_PER_N))
            else:
                root["contacts"][f]["point"].set_transform(HIDDEN)
                root["contacts"][f]["arrow"].set_transform(HIDDEN)
            target = frame["targets"][k] if frame.get("targets") is not None else None
            root["targets"][f].set_transform(_at(target) if target is not None else HIDDEN)
            link_force = frame.get("link_force")
            touching = link_force is not None and link_force[k] > self.link_touch_n
            # At the joint before the distal link: which link it is the log does not say.
            knuckle = poses.get(self.distal_links.get(f), None)
            root["link_touch"][f].set_transform(knuckle if touching and knuckle is not None
                                                else HIDDEN)


def _at(p):
    t = np.eye(4)
    t[:3, 3] = p
    return t


# The pose of a hidden object: scaled to nothing at the origin (an animation cannot add or remove
# objects; a hidden object that does not move costs no keys).
HIDDEN = np.diag([1e-6, 1e-6, 1e-6, 1.0])
HIDDEN.setflags(write=False)


def frame_text(frame):
    parts = [f"t = {frame['t']:.2f} s", frame.get("grasp_state", ""), frame.get("regrasp_state", "")]
    if frame.get("action"):
        parts.append(frame["action"])
    if frame.get("goals"):
        parts.append(frame["goals"])
    elif frame.get("rotation") is not None:
        parts.append(f"rotation {frame['rotation']:+.2f} rad")
    return "   ".join(p for p in parts if p)


# --- from a log -----------------------------------------------------------------------------------

def log_frames(data, config, fps):
    """The run resampled at `fps` on the truth channel's clock: one dict per frame."""
    o = data.object
    if len(o) == 0:
        raise ViewError("the log has no object truth (DMPL_SENSORS_TRUE)")
    truth = data.columns.table(channels.SENSORS_TRUE)
    joints = data.columns.channels.get(channels.SENSORS_TRUE, {}).get("joints", [])
    times = np.arange(o.t[0], o.t[-1] + 1e-9, 1.0 / fps)
    it = np.clip(np.searchsorted(o.t, times), 0, len(o) - 1)
    sensed = data.object_sensed
    sup = data.supervisor
    ctl = data.columns.table(channels.CONTROLLER_REPORT) or \
        data.columns.table(channels.CONTROLLER_STATUS)
    ctl_t = ctl["utime"] * 1e-6 if ctl else np.zeros(0)
    tasks = data.tasks
    _, axis = task_axis(config)
    rotation = cumulative_rotation(o["orientation"], axis)
    frames = []
    for t, i in zip(times, it):
        f = {"t": float(t - o.t[0]),
             "joints": dict(zip(joints, truth["joint_position"][i])) if joints else {},
             "object_position": o["position"][i], "object_orientation": o["orientation"][i],
             "force": data.tactile["force"][i], "in_contact": data.tactile["in_contact"][i],
             "link_force": data.tactile["link_force"][i],
             "gravity": data.gravity[i],
             "contact_position": truth["tactile_position"][i],
             "contact_normal": truth["tactile_normal"][i],
             "roles": [1] * len(data.fingers), "rotation": float(rotation[i] - rotation[0])}
        if len(sensed):
            j = min(int(np.searchsorted(sensed.t, t)), len(sensed) - 1)
            f["sensed_position"], f["sensed_orientation"] = (sensed["position"][j],
                                                             sensed["orientation"][j])
        if len(sup):
            j = max(int(np.searchsorted(sup.t, t, side="right")) - 1, 0)
            names = data.supervisor_fingers
            f["roles"] = [int(sup["roles"][j][names.index(n)]) if n in names else 1
                          for n in data.fingers]
            f["grasp_state"], f["regrasp_state"] = sup["grasp_state"][j], sup["regrasp_state"][j]
            f["action"] = sup["last_action"][j]
            if sup["has_orientation_goal"][j]:
                f["goal"] = sup["orientation_goal"][j]
                f["goals"] = (f"goals {int(sup['goals_reached'][j])}, "
                              f"{float(sup['goal_error'][j]):.2f} rad to go")
        if "goal" not in f and len(tasks):
            j = int(np.searchsorted(tasks.t, t, side="right")) - 1
            if j >= 0 and tasks["has_target"][j]:
                f["goal"] = tasks["orientation"][j]
        if len(ctl_t):
            j = int(np.searchsorted(ctl_t, t, side="right")) - 1
            if j >= 0:
                f["targets"] = ctl["target_position"][j]
        frames.append(f)
    return frames


def run_config(log_path):
    """The run's config beside its log (OUT/config.yaml) and its path; ({}, None) without."""
    path = Path(log_path).parent / "config.yaml"
    return (experiment.load_yaml(path), path) if path.exists() else ({}, None)


def read_frames(log_path, fps):
    """The frames of a recorded run and its config."""
    log_path = Path(log_path)
    if not log_path.is_file():
        raise ViewError(f"no such log '{log_path}'")
    config, path = run_config(log_path)
    with tempfile.TemporaryDirectory(prefix="dmpl-view-") as tmp:
        extract(log_path, tmp, FIELDS)
        return log_frames(LogData(Columns(tmp)), config, fps), config, path


class Recorder:
    """Stands in for the visualizer while drawing frames: collects each node's poses per frame,
    then becomes one Meshcat animation (tracks of positions and quaternions) in which a pose
    that does not change between frames is one key, not one per frame."""

    def __init__(self, path=()):
        self.path, self.frame, self.poses = path, 0, {}

    def __getitem__(self, name):
        child = Recorder(self.path + (name,))
        child.frame, child.poses = self.frame, self.poses
        return child

    def set_transform(self, matrix):
        self.poses.setdefault(self.path, []).append((self.frame, matrix))

    def animation(self, meshcat, vis, fps):
        anim = meshcat.animation.Animation(default_framerate=fps)
        for path, keys in self.poses.items():
            node = vis
            for name in path:
                node = node[name]
            clip = meshcat.animation.AnimationClip(fps=fps)
            tracks = {"position": [], "quaternion": [], "scale": []}
            poses = [_pose_key(m) for _, m in keys]
            frames = []
            for k, (frame, _) in enumerate(keys):
                # A run of equal poses keeps its first and last key (linear interpolation).
                if k in (0, len(keys) - 1) or poses[k] != poses[k - 1] or \
                        poses[k] != poses[k + 1]:
                    frames.append(frame)
                    for name, value in zip(tracks, poses[k]):
                        tracks[name].append(list(value))
            scaled = any(v != [1.0, 1.0, 1.0] for v in tracks["scale"])
            for name, jstype in (("position", "vector3"), ("quaternion", "quaternion"),
                                 ("scale", "vector3")):
                if name != "scale" or scaled:
                    clip.tracks[name] = meshcat.animation.AnimationTrack(
                        name, jstype, list(frames), tracks[name])
            anim.clips[node.path] = clip
        return anim


def _pose_key(m):
    """(position, [x, y, z, w] quaternion in three.js order, scale) of a 4x4 whose columns may
    be scaled, rounded to what a viewer can show (10 um, 1e-5)."""
    r = m[:3, :3]
    scale = np.linalg.norm(r, axis=0)
    if (scale < 1e-9).any():
        q = (0.0, 0.0, 0.0, 1.0)
    else:
        r = r / scale
        w = np.sqrt(max(0.0, 1 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
        x = np.copysign(np.sqrt(max(0.0, 1 + r[0, 0] - r[1, 1] - r[2, 2])) / 2, r[2, 1] - r[1, 2])
        y = np.copysign(np.sqrt(max(0.0, 1 - r[0, 0] + r[1, 1] - r[2, 2])) / 2, r[0, 2] - r[2, 0])
        z = np.copysign(np.sqrt(max(0.0, 1 - r[0, 0] - r[1, 1] + r[2, 2])) / 2, r[1, 0] - r[0, 1])
        q = (x, y, z, w)
    return (tuple(round(float(v), 5) for v in m[:3, 3]), tuple(round(float(v), 5) for v in q),
            tuple(round(float(v), 6) for v in scale))


def animate(scene, vis, frames, fps):
    scene.draw(vis, frames[0])  # what the page shows before it plays
    recorder = Recorder()
    for k, f in enumerate(frames):
        recorder.frame = k
        scene.draw(recorder, f)
    vis.set_animation(recorder.animation(scene.meshcat, vis, fps), play=False)


OVERLAY = """
<div id="dmpl-overlay" style="position:absolute;left:8px;top:8px;padding:4px 8px;
  font:13px monospace;color:#fff;background:rgba(0,0,0,.55);border-radius:4px;
  pointer-events:none;white-space:pre">{title}</div>
<script>
(function() {{
  const texts = {texts};
  const fps = {fps};
  const box = document.getElementById("dmpl-overlay");
  const title = box.textContent;
  function tick() {{
    const a = viewer.animator;
    const t = a && a.mixer ? a.mixer.time : 0;
    const k = Math.max(0, Math.min(texts.length - 1, Math.floor(t * fps)));
    box.textContent = title + "\\n" + texts[k];
    requestAnimationFrame(tick);
  }}
  requestAnimationFrame(tick);
}})();
</script>
"""


def write_html(vis, frames, fps, path, title):
    """The scene and its animation as one HTML file (Meshcat's own export: the viewer's script
    is inlined), with the text overlay driven by the animation's clock."""
    page = vis.static_html()
    texts = json.dumps([frame_text(f) for f in frames])
    overlay = OVERLAY.format(title=html.escape(title), texts=texts, fps=fps)
    page = page.replace("</body>", overlay + "</body>", 1)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(page)
    tmp.replace(path)
    return path


@contextlib.contextmanager
def replay(log_path, fps):
    """A log's scene and animation on a Meshcat server, closed on leaving:
    (visualizer, frames, title)."""
    frames, config, config_path = read_frames(log_path, fps)
    vis = open_visualizer()
    try:
        animate(Scene(vis, config, config_path), vis, frames, fps)
        name = config.get("experiment", {}).get("name", Path(log_path).stem)
        yield vis, frames, f"dmpl {name}: {Path(log_path).name}"
    finally:
        close_visualizer(vis)


def write_replay(log_path, html_path, fps=30.0):
    """The self-contained HTML replay of a log; its path."""
    with replay(log_path, fps) as (vis, frames, title):
        return write_html(vis, frames, fps, html_path, title)


def view_log(log_path, fps=30.0):
    """Serves a log's replay until Ctrl-C."""
    with replay(log_path, fps) as (vis, frames, _):
        print(f"view: open {vis.url()}  ({len(frames)} frames at {fps:g} Hz; Open Controls > "
              "Animations: play, pause, time to scrub, timeScale for the speed; Ctrl-C ends)",
              flush=True)
        _wait()


# --- live ---------------------------------------------------------------------------------------

class Latest:
    """Keeps the last raw message of each channel; decoding waits until a frame is drawn."""

    def __init__(self):
        self.lock = threading.Lock()
        self.raw = {}
        self.count = 0

    def __call__(self, channel, data):
        with self.lock:
            self.raw[channel] = data
            self.count += 1

    def take(self):
        with self.lock:
            raw, self.raw = self.raw, {}
            return raw


def live_frame(msgs, fingers, state):
    """Updates `state` (the last decoded values) from newly arrived raw messages; a frame once
    the truth has arrived."""
    from dmpl import hand_sensors_t, supervisor_status_t, task_cmd_t
    if channels.VIEW_TRUTH in msgs:
        state["truth"] = hand_sensors_t.decode(msgs[channels.VIEW_TRUTH])
    if channels.VIEW_SENSED in msgs:
        state["sensed"] = hand_sensors_t.decode(msgs[channels.VIEW_SENSED])
    if channels.SUPERVISOR_STATUS in msgs:
        state["sup"] = supervisor_status_t.decode(msgs[channels.SUPERVISOR_STATUS])
    if channels.TASK in msgs:
        state["task"] = task_cmd_t.decode(msgs[channels.TASK])
    s = state.get("truth")
    if s is None:
        return None
    by_name = {c.finger: c for c in s.tactile.fingers}
    f = {"t": s.utime * 1e-6, "joints": dict(zip(s.joints.name, s.joints.position)),
         "object_position": np.array(s.object.position),
         "object_orientation": np.array(s.object.orientation),
         "force": [by_name[n].force_n if n in by_name else 0.0 for n in fingers],
         "in_contact": [bool(by_name[n].in_contact) if n in by_name else False for n in fingers],
         "link_force": [by_name[n].link_force_n if n in by_name else 0.0 for n in fingers],
         "gravity": np.array(s.gravity),
         "contact_position": [np.array(by_name[n].position) if n in by_name else np.zeros(3)
                              for n in fingers],
         "contact_normal": [np.array(by_name[n].normal) if n in by_name else np.zeros(3)
                            for n in fingers],
         "roles": [1] * len(fingers)}
    if "sensed" in state:
        f["sensed_position"] = np.array(state["sensed"].object.position)
        f["sensed_orientation"] = np.array(state["sensed"].object.orientation)
    sup = state.get("sup")
    if sup is not None:
        roles = dict(zip(sup.finger, sup.role))
        f["roles"] = [int(roles.get(n, 1)) for n in fingers]
        f.update(grasp_state=sup.grasp_state, regrasp_state=sup.regrasp_state,
                 action=sup.last_action, rotation=sup.rotation_commanded_rad)
        if sup.has_orientation_goal:
            f["goal"] = np.array(sup.orientation_goal)
            f["goals"] = f"goals {sup.goals_reached}/{sup.num_goals}, " \
                         f"{sup.goal_error_rad:.2f} rad to go"
    task = state.get("task")
    if task is not None:
        if "goal" not in f and task.has_object_target:
            f["goal"] = np.array(task.object_orientation)
        # The points the supervisor sends fingers to (approach, explore).
        targets = {p.finger: np.array(p.target_position) for p in task.fingers if p.has_target}
        f["targets"] = [targets.get(n) for n in fingers]
    return f


def view_live(lcm_url, config, fps=15.0, duration_s=None, config_path=None):
    """Draws the running set until Ctrl-C (or duration_s)."""
    from .bus import Buses
    _, g = _meshcat()
    vis = open_visualizer()
    scene = Scene(vis, config, config_path)
    print(f"view: open {vis.url()}  (listening on {lcm_url}; Ctrl-C ends)", flush=True)
    latest = Latest()
    buses = Buses(lcm_url)
    # The simulator and the noise injector send the truth and the sensed channel for viewers at
    # run.view_rate_hz on a bus of their own: listening to them costs the loop a few copies
    # per frame (the 1 kHz buses would cost it one per tick).
    for ch in (channels.VIEW_TRUTH, channels.VIEW_SENSED, channels.SUPERVISOR_STATUS,
               channels.TASK):
        buses.subscribe(ch, latest)
    state, drawn, last_text, shown = {}, 0, 0.0, -1.0
    sink = ChangedOnly(vis)
    start = time.monotonic()
    try:
        while duration_s is None or time.monotonic() - start < duration_s:
            tick = time.monotonic()
            buses.handle(0)
            frame = live_frame(latest.take(), scene.fingers, state)
            if frame is not None:
                # The page's clock: x the sim time of the frame being drawn, y that of the last
                # frame drawn completely (a page, or a test, reads which instant it shows).
                clock = vis["dmpl"]["clock"]
                clock.set_transform(_at([frame["t"], shown, 0.0]))
                scene.draw(sink, frame)
                shown = frame["t"]
                clock.set_transform(_at([shown, shown, 0.0]))
                drawn += 1
                if tick - last_text > 0.25:
                    _live_text(vis, g, frame_text(frame))
                    last_text = tick
            time.sleep(max(0.0, 1.0 / fps - (time.monotonic() - tick)))
    except KeyboardInterrupt:
        pass
    finally:
        close_visualizer(vis)
    return {"frames": drawn, "messages": latest.count}


class ChangedOnly:
    """Stands in for the visualizer in the live loop: sends a node's transform only when it
    changed (every send is a round trip to the Meshcat server: hidden and resting objects cost
    nothing)."""

    def __init__(self, vis, sent=None, path=()):
        self.vis, self.sent, self.path = vis, {} if sent is None else sent, path

    def __getitem__(self, name):
        return ChangedOnly(self.vis[name], self.sent, self.path + (name,))

    def set_transform(self, matrix):
        key = _pose_key(matrix)
        if self.sent.get(self.path) != key:
            self.sent[self.path] = key
            self.vis.set_transform(matrix)


def _live_text(vis, g, text):
    texture = g.GenericTexture({"type": "_text", "text": text, "font_size": 24,
                                "font_face": "monospace"})
    vis["dmpl_text"].set_object(g.Mesh(g.Box([0.16, 0.0001, 0.04]),
                                       g.MeshBasicMaterial(map=texture, transparent=True)))
    t = np.eye(4)
    t[:3, 3] = [0.0, 0.12, 0.16]
    vis["dmpl_text"].set_transform(t)


def _wait():
    try:
        while True:
            time.sleep(1)
    except KeyboardInterrupt:
        pass


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl view", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log", nargs="?", help="a recorded run (OUT/run.lcmlog); live without it")
    ap.add_argument("--html", metavar="FILE", help="write a self-contained HTML replay and exit")
    ap.add_argument("--fps", type=float, help="frames per second (default: 30 from a log, 15 "
                    "live: each frame costs the live loop's machine a little)")
    ap.add_argument("--config", help="live: the run's config (OUT/config.yaml) for the object's "
                    "shape and the hand (default: configs/experiments/demo.yaml)")
    ap.add_argument("--lcm-url", help="live: the set's LCM URL (default: the config's run.lcm_url)")
    ap.add_argument("--duration", type=float, help="live: stop after this many seconds")
    args = ap.parse_args(argv)
    if args.fps is not None and not 1 <= args.fps <= 240:
        print("dmpl view: --fps must be in [1, 240]", file=sys.stderr)
        return 2
    try:
        if args.log and args.html:
            out = write_replay(args.log, args.html, args.fps or 30.0)
            print(f"replay: {out} ({out.stat().st_size / 1e6:.1f} MB)")
            return 0
        if args.log:
            view_log(args.log, args.fps or 30.0)
            return 0
        if args.html:
            print("dmpl view: --html needs a LOG", file=sys.stderr)
            return 2
        cfg_path = args.config or str(ROOT / "configs/experiments/demo.yaml")
        config = experiment.resolve(cfg_path, (), (), None)
        url = resolve_lcm_url(args.lcm_url, config.get("run", {}).get("lcm_url"))
        # The hand model reads the resolved config (an experiment's bases merged).
        resolved = tempfile.NamedTemporaryFile("w", suffix=".yaml", prefix="dmpl-view-",
                                               delete=False)
        with resolved:
            experiment.yaml.safe_dump(config, resolved)
        # The viewer and its server run only when a CPU has nothing else to do (SCHED_IDLE: a
        # woken process of the loop preempts them at once), so they never delay a tick.
        os.sched_setscheduler(0, os.SCHED_IDLE, os.sched_param(0))
        try:
            stats = view_live(url, config, args.fps or 15.0, args.duration, resolved.name)
        finally:
            os.unlink(resolved.name)
        print(f"view: drew {stats['frames']} frames of {stats['messages']} messages")
        return 0
    except (ViewError, LogError, experiment.ExperimentError, OSError) as e:
        print(f"dmpl view: {e}", file=sys.stderr)
        return 2
    except LcmUnavailable as e:
        print(f"dmpl view: {e}", file=sys.stderr)
        return 3


if __name__ == "__main__":
    sys.exit(main())
