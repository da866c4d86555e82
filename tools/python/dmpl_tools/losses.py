"""Why each recovery began, from recorded runs: the finger, the regrasp phase it fell in, and
what the simulator's truth shows of the finger at that moment.

    python -m dmpl_tools.losses RUN/run.lcmlog [RUN2/run.lcmlog ...] [--json FILE]
    tools/dmpl losses out/sweeps/NAME/*/seed*/run.lcmlog     # a sweep run with --record analysis

A recovery begins when the supervisor's grasp chart enters Recovering; its note says why: a grip
finger lost its contact, the object slipped or sank out of the grip while a finger explored
("sink": the controller's sink detector, caught by the supervisor, names the explorer), or a
finger rests on a link. For a lost contact the
truth tells how: the tip left the object while a link of the same finger took the load ("link
took the load": the link force above `metrics.link_contact_n` within 30 ms before to 100 ms
after the tip let go), the tip left it with no link on it ("tip came off"), or the tip still
touched when the controller counted it lost ("sensed only"). The phase is the regrasp chart's
action when the tip let go (dmpl_tools.phases names its kind), with how long it had lasted, and
the contact's angle round the tip from its front just before and as that phase began (the tip's
axis by forward kinematics of the true joints against the true normal: past ~95 deg the distal
link's box lies within a few millimetres of a flat surface). Needs the truth at least every 10
ticks: any record policy but none.
"""
import argparse
import json
import re
import sys
import tempfile
from collections import Counter
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from . import channels, experiment
from .hand_geometry import UrdfError, load_hand
from .logdata import Columns, LogData, LogError, extract
from .phases import kind

LINK_BEFORE_S = 0.03   # a link already on the object just before the tip let go...
LINK_AFTER_S = 0.10    # ...or within this after it: the link took the load
LOOK_BACK_S = 0.5      # the tip's letting go is looked for this far before the recovery


@dataclass
class Recovery:
    t: float              # s: the recovery began
    # link took the load | tip came off | sensed only | slip | sink | link rest | other
    cause: str
    finger: str           # '' where the cause names none
    phase: str            # the phase kind when it happened (dmpl_tools.phases.kind)
    action: str           # the regrasp chart's action then
    into_phase_s: float   # how long that action had lasted
    link_force_n: float   # the finger's most link force around the loss (truth); NaN: no finger
    contact_angle_deg: float  # round the tip from its front, just before it let go; NaN: unknown
    angle_at_phase_start_deg: float  # the same when the phase began (a placement, or a transition)
    recovered: bool       # the grasp chart went back to its tasks


def index_at(t, when):
    """The index of the last row of `t` at or before `when` (0 before the first)."""
    return max(int(np.searchsorted(t, when, side="right")) - 1, 0)


def _phase_at(sup, when):
    """(action, seconds it had lasted) of the supervisor's status at `when`."""
    t = np.asarray(sup.t, dtype=float)
    actions = sup["last_action"]
    i = index_at(t, when)
    start = i
    while start > 0 and actions[start - 1] == actions[i]:
        start -= 1
    return str(actions[i]), float(when - t[start])


def _reason(notes, i0, i1):
    for note in notes[i0:i1]:
        if str(note).startswith("recovering:"):
            return str(note)
    return ""


class ContactAngles:
    """A finger's contact angle round its tip (deg, 0: its front) at a row of the truth: the tip
    frame's axis (forward kinematics of the true joints) against the true normal."""

    def __init__(self, data, hand):
        truth = data.columns.table(channels.SENSORS_TRUE)
        self.names = data.columns.channels.get(channels.SENSORS_TRUE, {}).get("joints", [])
        self.q = truth.get("joint_position")
        self.normals = truth.get("tactile_normal")
        self.hand, self.fingers = hand, list(data.fingers)

    def __call__(self, f, i):
        if self.hand is None or self.q is None or self.normals is None or not self.names:
            return float("nan")
        poses = self.hand.link_poses(dict(zip(self.names, self.q[i])))
        tip = poses.get(self.fingers[f] + "_tip")
        normal = np.asarray(self.normals[i][f], dtype=float)
        if tip is None or not np.linalg.norm(normal) > 0.5:
            return float("nan")
        into = -normal / np.linalg.norm(normal)  # the normal points from the object into the tip
        return float(np.degrees(np.arccos(np.clip(tip[:3, 2] @ into, -1.0, 1.0))))


def _contact_loss(data, f, onset, link_n, angle_at):
    """(cause, when the tip let go, link force, contact angle) of finger f's lost contact before
    `onset`."""
    tac = data.tactile
    t = np.asarray(tac.t, dtype=float)
    i_on = index_at(t, onset)
    touching = np.asarray(tac["in_contact"][:, f], dtype=bool)
    link = np.nan_to_num(np.asarray(tac["link_force"][:, f], dtype=float))
    if touching[i_on]:
        return "sensed only", onset, float(link[i_on]), angle_at(f, i_on)
    i = i_on
    first = index_at(t, onset - LOOK_BACK_S)
    while i > first and not touching[i - 1]:
        i -= 1
    let_go = float(t[i])
    window = (t >= let_go - LINK_BEFORE_S) & (t <= let_go + LINK_AFTER_S)
    most = float(link[window].max()) if window.any() else 0.0
    angle = angle_at(f, max(i - 1, 0))
    return ("link took the load" if most > link_n else "tip came off"), let_go, most, angle


def recoveries(data, link_n=experiment.METRICS_DEFAULTS["link_contact_n"], angle_at=None):
    """[Recovery] of a LogData, in time order; `angle_at(f, truth row)`: the contact angle (deg;
    ContactAngles), or None."""
    angle_at = angle_at or (lambda f, i: float("nan"))
    sup = data.supervisor
    t = np.asarray(sup.t, dtype=float)
    states = [str(s) for s in sup["grasp_state"]]
    fingers = list(data.fingers)
    out = []
    for i in range(1, len(states)):
        if states[i] != "Recovering" or states[i - 1] == "Recovering":
            continue
        onset = float(t[i])
        reason = _reason(sup["note"], i, index_at(t, onset + 0.05) + 1)
        end = next((j for j in range(i, len(states)) if states[j] != "Recovering"), None)
        recovered = end is not None and states[end] == "Tasks"
        finger, cause, when, link, angle = "", "other", onset, float("nan"), float("nan")
        lost = re.search(r"finger (\w+) lost its grip contact", reason)
        rests = re.search(r"finger (\w+) rests on a link", reason)
        sinks = re.search(r"sinks out of the grip while (\w+) explores", reason)
        if lost and lost.group(1) in fingers:
            finger = lost.group(1)
            cause, when, link, angle = _contact_loss(data, fingers.index(finger), onset, link_n,
                                                     angle_at)
        elif rests:
            finger, cause = rests.group(1), "link rest"
        elif sinks:
            finger, cause = sinks.group(1), "sink"
        elif "slipped" in reason:
            cause = "slip"
        action, lasted = _phase_at(sup, when)
        before = float("nan")
        if finger and cause not in ("link rest", "sink"):
            f = fingers.index(finger)
            row = index_at(np.asarray(data.tactile.t, dtype=float), when - lasted)
            if data.tactile["in_contact"][row, f]:
                before = angle_at(f, row)
        out.append(Recovery(onset, cause, finger, kind(action), action, lasted, link, angle,
                            before, recovered))
    return out


def missing_channels(data):
    """What recoveries() reads that the run's data lacks (names; empty: nothing)."""
    return [what for what, rows in (("the supervisor's status", data.supervisor.t),
                                    ("the simulator's truth", data.tactile.t)) if not len(rows)]


def tally(recs):
    """Counter of (cause, phase kind) over recoveries."""
    return Counter((r.cause, r.phase) for r in recs)


def _run_settings(log):
    """(link contact threshold, hand or None) of the run whose log this is; a config that cannot
    be read leaves the defaults and no contact angles, and says so."""
    config = Path(log).parent / "config.yaml"
    link_n = experiment.METRICS_DEFAULTS["link_contact_n"]
    if not config.exists():
        return link_n, None
    try:
        metrics = experiment.load_yaml(config).get("metrics", {}) or {}
        link_n = float(metrics.get("link_contact_n", link_n))
        return link_n, load_hand(config)
    except (experiment.ExperimentError, UrdfError, AttributeError, TypeError, ValueError) as e:
        print(f"losses: {log}: the run's config: {e}; link contact at {link_n} N, no contact "
              "angles", file=sys.stderr)
        return link_n, None


@contextmanager
def read_run(log, prefix="dmpl-run-"):
    """A recorded run as (LogData, link contact threshold, hand or None), its columns kept on
    disk while the block runs (the contact angles read them); LogError for a missing log or one
    without the supervisor's status and the simulator's truth."""
    if not Path(log).is_file():
        raise LogError(f"no such log '{log}'")
    link_n, hand = _run_settings(log)
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        extract(log, tmp)
        data = LogData(Columns(tmp))
        missing = missing_channels(data)
        if missing:
            raise LogError(" and ".join(missing) + " missing (recorded with --record none, or "
                           "not a dmpl run)")
        yield data, link_n, hand


def _without_nan(v):
    """`v` with every NaN, however deep in dicts and lists, as None (JSON's null)."""
    if isinstance(v, float) and np.isnan(v):
        return None
    if isinstance(v, dict):
        return {k: _without_nan(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_without_nan(x) for x in v]
    return v


def write_rows(path, every, tool):
    """Writes [(log, dataclass row)] to `path` as JSON (NaN as null); False, said on stderr
    under the tool's name, when it cannot."""
    rows = [_without_nan(dict(asdict(r), log=str(log))) for log, r in every]
    try:
        Path(path).write_text(json.dumps(rows, indent=1, allow_nan=False))
    except OSError as e:
        print(f"{tool}: cannot write {path}: {e}", file=sys.stderr)
        return False
    return True


def _recoveries_of(log):
    """[Recovery] of one log."""
    with read_run(log, "dmpl-losses-") as (data, link_n, hand):
        return recoveries(data, link_n, ContactAngles(data, hand))


def _line(r):
    """One recovery, as the command prints it."""
    said = f"{r.t:7.2f} s {r.finger or '-':2s} {r.cause:18s} in '{r.action}' after " \
           f"{r.into_phase_s:.2f} s"
    if not np.isnan(r.link_force_n):
        said += f" link {r.link_force_n:.2f} N"
    if not np.isnan(r.contact_angle_deg):
        said += f", contact {r.contact_angle_deg:.0f} deg round the tip"
    if not np.isnan(r.angle_at_phase_start_deg):
        said += f" ({r.angle_at_phase_start_deg:.0f} as the phase began)"
    return said + ("" if r.recovered else " (not recovered)")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m dmpl_tools.losses", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+", help="runs' run.lcmlog")
    ap.add_argument("--json", help="write every recovery as JSON here")
    args = ap.parse_args(argv)
    every, failed, unwritten = [], 0, False  # every: (log, Recovery)
    for log in args.logs:
        try:
            found = _recoveries_of(log)
        except LogError as e:
            print(f"losses: {log}: {e}", file=sys.stderr)
            failed += 1
            continue
        for r in found:
            every.append((log, r))
            print(f"{log}: {_line(r)}")
    if args.json and not write_rows(args.json, every, "losses"):
        unwritten = True
    counts = tally([r for _, r in every])
    if counts:
        print(f"\n{'cause':20s} {'phase':22s} {'count':>5s}")
        for (cause, phase), n in counts.most_common():
            print(f"{cause:20s} {phase:22s} {n:5d}")
    print(f"{len(every)} recoveries in {len(args.logs) - failed} logs")
    # The logs that could be read are tallied; one that could not fails the command.
    return 2 if failed or unwritten else 0


if __name__ == "__main__":
    sys.exit(main())
