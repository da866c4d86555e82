"""A run's data as numpy arrays, from column files (components/logging/log_columns.h).

Columns come from two places, written by the same C++ code: the recorder extracts them online
from every message of a run (whatever its record policy keeps in the log), and `dmpl_logcols`
extracts them from any recorded log in one pass. Either way only the channels and fields a tool
asks for are decoded, into arrays, never message by message into Python objects; messages that
cannot be decoded, garbage between events and a truncated last event are counted (`problems`),
never fatal.
"""
import json
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import channels
from .paths import executable

ROLE_NAMES = {0: "free", 1: "grip", 2: "explore"}


class LogError(Exception):
    """A log or a column directory that cannot be read at all."""


@dataclass
class Series:
    """Rows of one channel: t (s, sim time) and named columns."""
    t: np.ndarray
    cols: dict = field(default_factory=dict)

    def __getitem__(self, key):
        return self.cols[key]

    def __len__(self):
        return len(self.t)


def fields_regex(fields):
    """{channel: [field, ...] or None (every field)} -> the regex dmpl_logcols --fields takes."""
    parts = []
    for channel, names in fields.items():
        parts.append(f"{channel}/.*" if names is None else f"{channel}/({'|'.join(names)})")
    return "^(" + "|".join(parts) + ")$"


def extract(log_path, out_dir, fields=None, channels_regex=".*"):
    """Runs dmpl_logcols over a log: one pass, the columns of `fields` (see fields_regex) into
    out_dir. Returns the meta. Raises LogError when the log cannot be read."""
    cmd = [executable("dmpl_logcols"), str(log_path), str(out_dir), "--channels", channels_regex]
    if fields is not None:
        cmd += ["--fields", fields_regex(fields)]
    done = subprocess.run(cmd, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        raise LogError(done.stderr.strip() or f"dmpl_logcols failed on {log_path}")
    return json.loads((Path(out_dir) / "meta.json").read_text())


class Columns:
    """The tables of a column directory: `table(channel)` -> {field: array}."""

    def __init__(self, path):
        self.path = Path(path)
        try:
            self.meta = json.loads((self.path / "meta.json").read_text())
        except (OSError, ValueError) as e:
            raise LogError(f"{self.path}: no readable meta.json ({e})") from None
        self.channels = self.meta.get("channels", {})

    def rows(self, channel):
        return self.channels.get(channel, {}).get("rows", 0)

    def table(self, channel, sub=""):
        info = self.channels.get(channel)
        folder = self.path / channel / sub if sub else self.path / channel
        if not info or not folder.is_dir():
            return {}
        out = {f.stem: np.load(f) for f in sorted(folder.glob("*.npy"))}
        strings = info.get("event_strings" if sub else "strings", {})
        for name, table in strings.items():
            if name in out:
                names = np.array(table, dtype=object)
                out[name] = names[out[name]] if len(names) else out[name].astype(object)
        seq = out.get("seq")
        if not sub and seq is not None and len(seq) > 1 and (np.diff(seq) < 0).any():
            # A message sent again after a loss is logged when it arrived: rows in tick order.
            order = np.argsort(seq, kind="stable")
            out = {k: v[order] if len(v) == len(seq) else v for k, v in out.items()}
        return out

    def problems(self):
        """What could not be read, one line each."""
        out = []
        for channel, info in self.channels.items():
            for reason, n in info.get("rejected_by_reason", {}).items():
                out.append(f"{channel}: {n} messages skipped ({reason})")
        source = self.meta.get("source", {})
        if source.get("skipped_bytes"):
            out.append(f"log: {source['skipped_bytes']} bytes that were not events skipped at "
                       f"{source['resyncs']} places")
        if source.get("truncated"):
            out.append("log: the last event is truncated")
        return out


def _t(table):
    return table["utime"] * 1e-6 if "utime" in table else np.zeros(0)


def _get(table, key, shape_tail=(), dtype=float):
    """A column, or an empty array of the right shape when the table lacks it."""
    if key in table:
        return table[key]
    n = len(table.get("utime", ()))
    return np.zeros((n, *shape_tail), dtype=dtype)


class LogData:
    """The data of a run that metrics, the report and the viewer read."""

    def __init__(self, columns):
        self.columns = columns
        self.problems = columns.problems()
        truth = columns.table(channels.SENSORS_TRUE)
        sensed = columns.table(channels.SENSORS)
        meta_truth = columns.channels.get(channels.SENSORS_TRUE, {})
        self.fingers = list(meta_truth.get("fingers", []))
        self.truth_seq = truth.get("seq", np.zeros(0, dtype=np.int64))
        self.object = self._poses(truth)
        self.object_sensed = self._poses(sensed)
        nf = len(self.fingers)
        self.tactile = Series(_t(truth), {
            "force": _get(truth, "tactile_force", (nf,)),
            # NaN in logs from before the simulator published it.
            "link_force": _get(truth, "tactile_link_force", (nf,)) if "tactile_link_force" in truth
            else np.full((len(_t(truth)), nf), np.nan),
            "in_contact": _get(truth, "tactile_in_contact", (nf,), bool),
            "position": _get(truth, "tactile_position", (nf, 3))})
        # Gravity in the palm frame (m/s^2); NaN in logs from before the simulator published it.
        self.gravity = (_get(truth, "gravity", (3,)) if "gravity" in truth
                        else np.full((len(_t(truth)), 3), np.nan))
        self._read_sim(columns)
        self._read_supervisor(columns)
        self._read_controller(columns)
        task = columns.table(channels.TASK)
        self.tasks = Series(_t(task), {
            "has_target": _get(task, "has_object_target", (), bool),
            "orientation": _get(task, "object_orientation", (4,))})

    @classmethod
    def from_log(cls, log_path, fields=None):
        """Extracts the columns of a log into a temporary directory and loads them."""
        if not Path(log_path).is_file():
            raise LogError(f"no such log '{log_path}'")
        with tempfile.TemporaryDirectory(prefix="dmpl-cols-") as tmp:
            extract(log_path, tmp, fields)
            return cls(Columns(tmp))

    @staticmethod
    def _poses(table):
        return Series(_t(table), {"position": _get(table, "object_position", (3,)),
                                  "orientation": _get(table, "object_orientation", (4,)),
                                  "valid": _get(table, "object_valid", (), bool)})

    def _read_sim(self, columns):
        # Requests to the simulator: on SIM_CONTROL (people, tools) and with the supervisor's
        # tasks (task_cmd_t.sim_command, acting as a SIM_CONTROL of the task's seq would).
        control = columns.table(channels.SIM_CONTROL)
        task = columns.table(channels.TASK)
        self.controls = sorted(
            list(zip(control.get("seq", []), control.get("command", []),
                     control.get("reason", []))) +
            [(s, c, r) for s, c, r in zip(task.get("seq", []), task.get("sim_command", []),
                                          task.get("sim_command_reason", [])) if c != 0],
            key=lambda c: c[0])
        status = columns.table(channels.SIM_STATUS)
        self.sim_status = None
        if len(status.get("seq", ())):
            self.sim_status = {k: v[-1] for k, v in status.items()}

    def _read_supervisor(self, columns):
        sup = columns.table(channels.SUPERVISOR_STATUS)
        self.supervisor_fingers = list(
            columns.channels.get(channels.SUPERVISOR_STATUS, {}).get("fingers", []))
        self.supervisor = Series(_t(sup), {
            "grasp_state": list(sup.get("grasp_state", [])),
            "regrasp_state": list(sup.get("regrasp_state", [])),
            "roles": _get(sup, "role", (len(self.supervisor_fingers),), int).astype(int),
            "rotation_commanded": _get(sup, "rotation_commanded_rad"),
            "regrasps": _get(sup, "regrasps", (), int),
            "recoveries": _get(sup, "recoveries", (), int),
            "finished": _get(sup, "finished", (), bool),
            "failed": _get(sup, "failed", (), bool),
            "last_action": list(sup.get("last_action", [""] * len(_t(sup)))),
            "note": list(sup.get("note", [""] * len(_t(sup)))),
            "goals_reached": _get(sup, "goals_reached", (), int),
            "has_orientation_goal": _get(sup, "has_orientation_goal", (), bool),
            "orientation_goal": _get(sup, "orientation_goal", (4,)),
            "goal_error": _get(sup, "goal_error_rad")})

    def _read_controller(self, columns):
        # The per-tick status when it was kept at every tick; else the 100 Hz report (the
        # analysis policy keeps the status in bursts only), which carries every event too.
        status, report = channels.CONTROLLER_STATUS, channels.CONTROLLER_REPORT
        use = status if columns.rows(status) >= 5 * columns.rows(report) else report
        ctl = columns.table(use)
        nf = len(columns.channels.get(use, {}).get("fingers", []))
        events = columns.table(use, "events")
        self.controller = Series(_t(ctl), {
            "desired_force": _get(ctl, "desired_force", (nf,)),
            "force": _get(ctl, "force", (nf,)),  # what the tip's sensor reads
            # The grip force planned per finger (adapted to the load); NaN in logs without it.
            "grip_force": ctl["grip_force_n"] if "grip_force_n" in ctl
            else np.full(len(_t(ctl)), np.nan),
            "role": _get(ctl, "role", (nf,), int).astype(int),
            # What the controller has observed of the object (0: not yet; NaN in older logs).
            "observed_friction": ctl["observed_friction"] if "observed_friction" in ctl
            else np.full(len(_t(ctl)), np.nan),
            "observed_weight": ctl["observed_weight_n"] if "observed_weight_n" in ctl
            else np.full(len(_t(ctl)), np.nan),
            "events": list(zip(_t(events), events.get("type", []), events.get("finger", []),
                               events.get("text", [])))})

    def truth_tick_step(self):
        """The usual seq step between truth rows (1 at every tick, 10 in an analysis log)."""
        if len(self.truth_seq) < 2:
            return 1
        return max(int(np.median(np.diff(self.truth_seq))), 1)

    def time_of_seq(self, seq):
        """The time of the truth row of `seq`, or of the nearest one."""
        if not len(self.truth_seq):
            return 0.0
        i = int(np.searchsorted(self.truth_seq, seq))
        candidates = [j for j in (i - 1, i) if 0 <= j < len(self.truth_seq)]
        j = min(candidates, key=lambda k: (abs(int(self.truth_seq[k]) - seq), k))
        return float(self.object.t[j])


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


def task_axis(config):
    """task.axis of a config (x, y, z or a vector) -> (label, unit vector); x when unreadable
    (the supervisor has already rejected a bad one)."""
    value = (config or {}).get("task", {}).get("axis", "x")
    if isinstance(value, str):
        return (value, AXES[value]) if value in AXES else ("x", AXES["x"])
    try:
        v = np.asarray(value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        return "x", AXES["x"]
    n = np.linalg.norm(v)
    if not np.isfinite(n) or n < 1e-6:
        return "x", AXES["x"]
    return "[" + ", ".join(f"{x:.3g}" for x in v / n) + "]", v / n


def cumulative_rotation(quats, axis):
    """Signed rotation about `axis` (palm frame) accumulated step by step, so whole turns add up."""
    if len(quats) < 2:
        return np.zeros(len(quats))
    steps = rotation_vector(quat_mul(quats[1:], quat_conj(quats[:-1])))  # palm-frame increments
    return np.concatenate([[0.0], np.cumsum(steps @ axis)])
