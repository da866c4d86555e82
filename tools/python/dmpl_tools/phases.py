"""Where a gait's time goes: how long each kind of regrasp phase lasted, from a recorded run.

    python -m dmpl_tools.phases RUN_DIR/run.lcmlog     # any record policy but none

A phase is a stretch of the supervisor's status with one `last_action` (the regrasp chart's
action: "A4 R explore", "A3 R grip + A1 TFMR rotate", ...); it lasts until the next action or
grasp state (a recovery, the end). Phases are grouped by kind (explore, explore while three turn,
grip, grip while four turn, four-finger turn, three-finger turn) and per finger, with the mean
cycle (the tasks' time over the regrasps) at the end. The status comes at 100 Hz, so durations
are multiples of 10 ms.
"""
import argparse
import sys
from collections import defaultdict

import numpy as np

from .logdata import LogData, LogError


def kind(action):
    """The phase kind of a regrasp chart action's name."""
    if "explore" in action:
        return "explore + three turn" if "rotate" in action else "explore"
    if "grip" in action:
        return "grip + four turn" if "rotate" in action else "grip"
    if action.startswith("A1 "):
        return "four-finger turn"
    if "rotate" in action:
        return "three-finger turn"
    return action or "-"


def phases(data):
    """[(action, grasp state, start s, duration s)] from a LogData's supervisor status."""
    sup = data.supervisor
    t = np.asarray(sup.t, dtype=float)
    out = []
    start, key = None, None
    for ti, action, state in zip(t, sup["last_action"], sup["grasp_state"]):
        if (action, state) != key:
            if key is not None:
                out.append((key[0], key[1], start, ti - start))
            key, start = (action, state), ti
    if key is not None and len(t):
        out.append((key[0], key[1], start, t[-1] - start))
    return out


def summarize(rows, in_tasks="Tasks"):
    """{(kind, finger): (count, total s)} over the chart's phases in the grasp state `in_tasks`
    (not recoveries); finger '' is every finger's, per finger only where one finger acts."""
    totals = defaultdict(lambda: [0, 0.0])
    for action, state, _, duration in rows:
        if str(state) != in_tasks or not action.startswith("A"):
            continue
        k = kind(action)
        keys = [(k, "")]
        if k in ("explore", "explore + three turn", "grip", "grip + four turn"):
            keys.append((k, action.split()[1]))
        for key in keys:
            totals[key][0] += 1
            totals[key][1] += duration
    return {k: tuple(v) for k, v in totals.items()}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m dmpl_tools.phases", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log", help="a run's run.lcmlog")
    args = ap.parse_args(argv)
    try:
        data = LogData.from_log(args.log)
    except LogError as e:
        print(f"phases: {e}", file=sys.stderr)
        return 2
    rows = phases(data)
    totals = summarize(rows)
    if not totals:
        print("phases: no regrasp phase in this log", file=sys.stderr)
        return 1
    print(f"{'phase':22s} {'finger':6s} {'count':>5s} {'mean s':>7s} {'total s':>8s}")
    for (k, finger), (n, total) in sorted(totals.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        print(f"{k:22s} {finger or 'all':6s} {n:5d} {total / n:7.3f} {total:8.2f}")
    regrasps = int(np.max(data.supervisor["regrasps"])) if len(data.supervisor.t) else 0
    tasks = sum(total for (k, finger), (n, total) in totals.items() if finger == "")
    if regrasps:
        print(f"{regrasps} regrasps; {tasks:.2f} s in regrasp phases: {tasks / regrasps:.3f} s "
              "per cycle")
    return 0


if __name__ == "__main__":
    sys.exit(main())
