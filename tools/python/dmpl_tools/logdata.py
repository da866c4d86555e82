"""Reads a dmpl LCM log into numpy arrays, one table per channel we care about."""
import gc
from dataclasses import dataclass, field

import lcm
import numpy as np

from . import channels

ROLE_NAMES = {0: "free", 1: "grip", 2: "explore"}


@dataclass
class Series:
    """Rows of one channel: t (s, sim time) and named columns."""
    t: np.ndarray
    cols: dict = field(default_factory=dict)

    def __getitem__(self, key):
        return self.cols[key]

    def __len__(self):
        return len(self.t)


def _matrix(rows, dtype=float):
    """A 2-D array of rows (each a list); (0, 0) when there are none."""
    return np.array(rows, dtype=dtype) if rows else np.zeros((0, 0), dtype=dtype)


class LogData:
    """The decoded content of a run's log."""

    def __init__(self, path):
        # Decoding makes millions of small objects and no cycles: the cyclic collector would
        # walk them again and again (a 120 s run decodes in 25 s without it, 46 s with it).
        was_enabled = gc.isenabled()
        gc.disable()
        try:
            self._read(path)
        finally:
            if was_enabled:
                gc.enable()

    def _read(self, path):
        from dmpl import (controller_status_t, hand_sensors_t, sim_control_t, sim_status_t,
                          supervisor_status_t, task_cmd_t)
        decoders = {
            channels.SENSORS_TRUE: hand_sensors_t, channels.SENSORS: hand_sensors_t,
            channels.SIM_CONTROL: sim_control_t,
            channels.SIM_STATUS: sim_status_t, channels.SUPERVISOR_STATUS: supervisor_status_t,
            channels.CONTROLLER_STATUS: controller_status_t, channels.TASK: task_cmd_t,
        }
        raw = {c: [] for c in decoders}
        self.wall_first = self.wall_last = None
        log = lcm.EventLog(str(path), "r")
        for event in log:
            if self.wall_first is None:
                self.wall_first = event.timestamp
            self.wall_last = event.timestamp
            decoder = decoders.get(event.channel)
            if decoder is None:
                continue
            try:
                raw[event.channel].append(decoder.decode(event.data))
            except ValueError:
                continue
        log.close()
        self.raw = raw
        self.fingers = []
        truth = [m.object for m in raw[channels.SENSORS_TRUE]]
        self.seq_to_t = {m.seq: m.utime * 1e-6 for m in truth}
        self.object = self._poses(truth)
        self.object_sensed = self._poses([m.object for m in raw[channels.SENSORS]])
        tact = [m.tactile for m in raw[channels.SENSORS_TRUE]]
        if tact:
            self.fingers = [f.finger for f in tact[0].fingers]
        self.tactile = Series(
            np.array([m.utime * 1e-6 for m in tact]),
            {"force": _matrix([[f.force_n for f in m.fingers] for m in tact]),
             "in_contact": _matrix([[f.in_contact for f in m.fingers] for m in tact], bool)})
        self.sim_status = raw[channels.SIM_STATUS]
        self.controls = [(m.seq, m.command, m.reason) for m in raw[channels.SIM_CONTROL]]
        sup = raw[channels.SUPERVISOR_STATUS]
        self.supervisor = Series(
            np.array([m.utime * 1e-6 for m in sup]),
            {"grasp_state": [m.grasp_state for m in sup],
             "regrasp_state": [m.regrasp_state for m in sup],
             "roles": _matrix([list(m.role) for m in sup], int),
             "finger": [list(m.finger) for m in sup],
             "rotation_commanded": np.array([m.rotation_commanded_rad for m in sup]),
             "regrasps": np.array([m.regrasps for m in sup]),
             "finished": np.array([m.finished for m in sup], dtype=bool),
             "failed": np.array([m.failed for m in sup], dtype=bool),
             "last": sup[-1] if sup else None})
        ctl = raw[channels.CONTROLLER_STATUS]
        self.controller = Series(
            np.array([m.utime * 1e-6 for m in ctl]),
            {"desired_force": _matrix([[f.desired_force_n for f in m.fingers] for m in ctl]),
             "role": _matrix([[f.role for f in m.fingers] for m in ctl], int),
             "events": [(m.utime * 1e-6, e.type, e.finger, e.text) for m in ctl for e in m.events]})
        tasks = raw[channels.TASK]
        self.tasks = Series(
            np.array([m.utime * 1e-6 for m in tasks]),
            {"has_target": np.array([m.has_object_target for m in tasks], dtype=bool),
             "orientation": np.array([list(m.object_orientation) for m in tasks]).reshape(-1, 4)})

    @staticmethod
    def _poses(msgs):
        return Series(np.array([m.utime * 1e-6 for m in msgs]),
                      {"position": np.array([list(m.position) for m in msgs]).reshape(-1, 3),
                       "orientation": np.array([list(m.orientation) for m in msgs]).reshape(-1, 4),
                       "valid": np.array([m.valid for m in msgs], dtype=bool)})

    def time_of_seq(self, seq):
        if seq in self.seq_to_t:
            return self.seq_to_t[seq]
        if not self.seq_to_t:
            return 0.0
        return self.seq_to_t[min(self.seq_to_t, key=lambda s: abs(s - seq))]


# --- quaternion helpers (w, x, y, z) ----------------------------------------------------------
def quat_mul(a, b):
    w1, x1, y1, z1 = np.moveaxis(a, -1, 0)
    w2, x2, y2, z2 = np.moveaxis(b, -1, 0)
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], axis=-1)


def quat_conj(q):
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def rotation_vector(q):
    """Rotation vectors of unit quaternions (shortest rotation)."""
    q = np.where(q[..., :1] < 0, -q, q)
    v = q[..., 1:]
    s = np.linalg.norm(v, axis=-1)
    angle = 2.0 * np.arctan2(s, q[..., 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        axis = np.where(s[..., None] > 1e-12, v / s[..., None], 0.0)
    return axis * angle[..., None]


def angle_between(q1, q2):
    return np.linalg.norm(rotation_vector(quat_mul(q2, quat_conj(q1))), axis=-1)


AXES = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}


def cumulative_rotation(quats, axis):
    """Signed rotation about `axis` (palm frame) accumulated step by step, so whole turns add up."""
    if len(quats) < 2:
        return np.zeros(len(quats))
    steps = rotation_vector(quat_mul(quats[1:], quat_conj(quats[:-1])))  # palm-frame increments
    return np.concatenate([[0.0], np.cumsum(steps @ axis)])
