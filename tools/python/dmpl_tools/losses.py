"""Why each recovery began, from recorded runs: the finger, the regrasp phase it fell in, and
what the simulator's truth shows of the finger at that moment.

    python -m dmpl_tools.losses RUN/run.lcmlog [RUN2/run.lcmlog ...] [--json FILE]
    tools/dmpl losses out/sweeps/NAME/*/seed*/run.lcmlog     # a sweep run with --record analysis

A recovery begins when the supervisor's grasp chart enters Recovering; its note says why: a grip
finger lost its contact, the object slipped, or a finger rests on a link. For a lost contact the
truth tells how: the tip left the object while a link of the same finger took the load ("link
took the load": the link force above `metrics.link_contact_n` within 30 ms before to 100 ms
after the tip let go), the tip left it with no link on it ("tip came off"), or the tip still
touched when the controller counted it lost ("sensed only"). The phase is the regrasp chart's
action when the tip let go (dmpl_tools.phases names its kind), with how long it had lasted.
Needs the truth at least every 10 ticks: any record policy but none.
"""
import argparse
import json
import re
import sys
from collections import Counter
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from . import experiment
from .logdata import LogData, LogError
from .phases import kind

LINK_BEFORE_S = 0.03   # a link already on the object just before the tip let go...
LINK_AFTER_S = 0.10    # ...or within this after it: the link took the load
LOOK_BACK_S = 0.5      # the tip's letting go is looked for this far before the recovery


@dataclass
class Recovery:
    t: float              # s: the recovery began
    cause: str            # link took the load | tip came off | sensed only | slip | link rest | other
    finger: str           # '' where the cause names none
    phase: str            # the phase kind when it happened (dmpl_tools.phases.kind)
    action: str           # the regrasp chart's action then
    into_phase_s: float   # how long that action had lasted
    link_force_n: float   # the finger's most link force around the loss (truth); NaN: no finger
    recovered: bool       # the grasp chart went back to its tasks


def _index_at(t, when):
    return max(int(np.searchsorted(t, when, side="right")) - 1, 0)


def _phase_at(sup, when):
    """(action, seconds it had lasted) of the supervisor's status at `when`."""
    t = np.asarray(sup.t, dtype=float)
    actions = sup["last_action"]
    i = _index_at(t, when)
    start = i
    while start > 0 and actions[start - 1] == actions[i]:
        start -= 1
    return str(actions[i]), float(when - t[start])


def _reason(notes, i0, i1):
    for note in notes[i0:i1]:
        if str(note).startswith("recovering:"):
            return str(note)
    return ""


def _contact_loss(data, f, onset, link_n):
    """(cause, when the tip let go, link force) of finger f's lost contact before `onset`."""
    tac = data.tactile
    t = np.asarray(tac.t, dtype=float)
    i_on = _index_at(t, onset)
    touching = np.asarray(tac["in_contact"][:, f], dtype=bool)
    link = np.nan_to_num(np.asarray(tac["link_force"][:, f], dtype=float))
    if touching[i_on]:
        return "sensed only", onset, float(link[i_on])
    i = i_on
    first = _index_at(t, onset - LOOK_BACK_S)
    while i > first and not touching[i - 1]:
        i -= 1
    let_go = float(t[i])
    window = (t >= let_go - LINK_BEFORE_S) & (t <= let_go + LINK_AFTER_S)
    most = float(link[window].max()) if window.any() else 0.0
    return ("link took the load" if most > link_n else "tip came off"), let_go, most


def recoveries(data, link_n=experiment.METRICS_DEFAULTS["link_contact_n"]):
    """[Recovery] of a LogData, in time order."""
    sup = data.supervisor
    t = np.asarray(sup.t, dtype=float)
    states = [str(s) for s in sup["grasp_state"]]
    fingers = list(data.fingers)
    out = []
    for i in range(1, len(states)):
        if states[i] != "Recovering" or states[i - 1] == "Recovering":
            continue
        onset = float(t[i])
        reason = _reason(sup["note"], i, _index_at(t, onset + 0.05) + 1)
        end = next((j for j in range(i, len(states)) if states[j] != "Recovering"), None)
        recovered = end is not None and states[end] == "Tasks"
        finger, cause, when, link = "", "other", onset, float("nan")
        lost = re.search(r"finger (\w+) lost its grip contact", reason)
        rests = re.search(r"finger (\w+) rests on a link", reason)
        if lost and lost.group(1) in fingers:
            finger = lost.group(1)
            cause, when, link = _contact_loss(data, fingers.index(finger), onset, link_n)
        elif rests:
            finger, cause = rests.group(1), "link rest"
        elif "slipped" in reason:
            cause = "slip"
        action, lasted = _phase_at(sup, when)
        out.append(Recovery(onset, cause, finger, kind(action), action, lasted, link, recovered))
    return out


def tally(recs):
    """Counter of (cause, phase kind) over recoveries."""
    return Counter((r.cause, r.phase) for r in recs)


def _link_threshold(log):
    config = Path(log).parent / "config.yaml"
    if config.exists():
        metrics = (experiment.load_yaml(config) or {}).get("metrics", {}) or {}
        return float(metrics.get("link_contact_n", experiment.METRICS_DEFAULTS["link_contact_n"]))
    return experiment.METRICS_DEFAULTS["link_contact_n"]


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m dmpl_tools.losses", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+", help="runs' run.lcmlog")
    ap.add_argument("--json", help="write every recovery as JSON here")
    args = ap.parse_args(argv)
    every, failed = [], 0
    for log in args.logs:
        try:
            data = LogData.from_log(log)
        except LogError as e:
            print(f"losses: {log}: {e}", file=sys.stderr)
            failed += 1
            continue
        for r in recoveries(data, _link_threshold(log)):
            every.append(dict(asdict(r), log=str(log)))
            link = "" if np.isnan(r.link_force_n) else f" link {r.link_force_n:.2f} N"
            print(f"{log}: {r.t:7.2f} s {r.finger or '-':2s} {r.cause:18s} in '{r.action}' "
                  f"after {r.into_phase_s:.2f} s{link}{'' if r.recovered else ' (not recovered)'}")
    if args.json:
        Path(args.json).write_text(json.dumps(every, indent=1))
    counts = Counter((r["cause"], r["phase"]) for r in every)
    if counts:
        print(f"\n{'cause':20s} {'phase':22s} {'count':>5s}")
        for (cause, phase), n in counts.most_common():
            print(f"{cause:20s} {phase:22s} {n:5d}")
    print(f"{len(every)} recoveries in {len(args.logs) - failed} logs")
    return 2 if failed == len(args.logs) else 0


if __name__ == "__main__":
    sys.exit(main())
