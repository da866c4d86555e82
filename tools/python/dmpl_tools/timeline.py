"""What happened, row by row, over a stretch of a recorded run: the object, each finger's push
and contact, and what the supervisor and the controller said, in time order.

    python -m dmpl_tools.timeline RUN/run.lcmlog --from S [--to S] [--every S] [--json FILE]
    tools/dmpl timeline out/runs/NAME/run.lcmlog --from 3.3 --to 3.9   # around a loss

A loss (`tools/dmpl losses`) says when and how a finger let go; the timeline shows what led to
it. Each row, from the simulator's truth unless said:
  - the object's centre (mm, palm frame) and how far it has sunk along gravity since --from;
  - per finger: its role (g grip, e explore, - free) and the push the controller asked and its
    sensor read (N, the controller's report); the true tip force; its contact's elevation above
    the level through the object's centre, against gravity (deg: a pinch above it pushes the
    object down, and on a slick object friction cannot carry that); its contact's angle round the
    tip from its front (deg: past ~95 the distal link lies within millimetres of a flat
    surface); and the force on its links, when any.
Between the rows: the regrasp chart's actions and the supervisor's notes as they change, and the
controller's events ("R touches", "F lost its grip contact", ...). Needs the truth at least every
10 ticks: any record policy but none.
"""
import argparse
import sys
from dataclasses import dataclass, field

import numpy as np

from .logdata import LogError
from .losses import ContactAngles, index_at, read_run, write_rows

EVERY_S = 0.02
ROLE_LETTERS = {0: "-", 1: "g", 2: "e"}


@dataclass
class FingerRow:
    role: str               # g grip, e explore, - free (the controller's)
    asked_n: float          # the push the controller asked
    sensed_n: float         # what its sensor read (the controller's report)
    tip_n: float            # the true tip force
    link_n: float           # the true force on its links
    elevation_deg: float    # the contact above the level through the centre; NaN: no contact
    round_tip_deg: float    # the contact's angle round the tip from its front; NaN: unknown


@dataclass
class Row:
    t: float
    object_mm: list         # the object's centre, palm frame
    sink_mm: float          # along gravity since the first row (NaN without gravity sensed)
    fingers: dict = field(default_factory=dict)  # name -> FingerRow


def elevation_deg(contact, centre, gravity):
    """The contact's elevation above the level through `centre`, against `gravity` (deg); NaN
    when gravity is not sensed or the contact sits at the centre."""
    g = np.asarray(gravity, dtype=float)
    out = np.asarray(contact, dtype=float) - np.asarray(centre, dtype=float)
    if not (np.linalg.norm(g) > 1e-6 and np.linalg.norm(out) > 1e-9):
        return float("nan")
    up = -g / np.linalg.norm(g)
    return float(np.degrees(np.arcsin(np.clip(out @ up / np.linalg.norm(out), -1.0, 1.0))))


def timeline(data, start, end, every=EVERY_S, angle_at=None):
    """([Row], [(t, text)]) over [start, end] of a LogData: a row at most every `every` s of
    the truth, and the supervisor's and the controller's words as they came. `angle_at(f, i)`
    gives finger f's angle round its tip at truth row i (NaN when not given)."""
    tac = data.tactile
    t = np.asarray(tac.t, dtype=float)
    pos = np.asarray(data.object["position"], dtype=float)
    gravity = np.asarray(data.gravity, dtype=float)
    ctl = data.controller
    ct = np.asarray(ctl.t, dtype=float)
    rows, last = [], -np.inf
    first = None
    for i in np.flatnonzero((t >= start) & (t <= end)):
        if t[i] - last < every - 1e-9:
            continue
        last = t[i]
        if first is None:
            first = i
        g = gravity[i] if len(gravity) > i else np.full(3, np.nan)
        sink = float("nan")
        if np.all(np.isfinite(g)) and np.linalg.norm(g) > 1e-6:
            sink = float(1e3 * (pos[i] - pos[first]) @ (g / np.linalg.norm(g)))
        row = Row(float(t[i]), [float(v) for v in 1e3 * pos[i]], sink)
        j = index_at(ct, t[i]) if len(ct) else -1
        for f, name in enumerate(data.fingers):
            touching = bool(tac["in_contact"][i, f])
            row.fingers[name] = FingerRow(
                role=ROLE_LETTERS.get(int(ctl["role"][j, f]), "?") if j >= 0 else "?",
                asked_n=float(ctl["desired_force"][j, f]) if j >= 0 else float("nan"),
                sensed_n=float(ctl["force"][j, f]) if j >= 0 else float("nan"),
                tip_n=float(tac["force"][i, f]),
                link_n=float(np.nan_to_num(tac["link_force"][i, f])),
                elevation_deg=elevation_deg(tac["position"][i, f], pos[i], g) if touching
                else float("nan"),
                round_tip_deg=float(angle_at(f, i)) if angle_at is not None and touching
                else float("nan"))
        rows.append(row)
    return rows, _words(data, start, end)


def _words(data, start, end):
    """[(t, text)]: the chart's action and the supervisor's note when either changes, and the
    controller's events, within [start, end]."""
    words = []
    sup = data.supervisor
    said = None
    for ti, action, state, note in zip(sup.t, sup["last_action"], sup["grasp_state"],
                                       sup["note"]):
        key = (str(action), str(state), str(note))
        if key != said and start <= ti <= end:
            words.append((float(ti), f"[{action or '-'} | {state}] {note}".rstrip()))
        said = key
    for ti, _, _, text in data.controller["events"]:
        if start <= ti <= end:
            words.append((float(ti), f"controller: {text}"))
    return sorted(words, key=lambda w: w[0])


def _cell(r):
    """One finger's part of a printed row."""
    def num(v, fmt):
        return format(v, fmt) if np.isfinite(v) else "-".rjust(len(format(0.0, fmt)))
    cell = (f"{r.role} {num(r.asked_n, '4.2f')}>{num(r.sensed_n, '4.2f')} "
            f"tip {num(r.tip_n, '4.2f')} up {num(r.elevation_deg, '+4.0f')} "
            f"rd {num(r.round_tip_deg, '3.0f')}")
    return cell + (f" LINK {r.link_n:.2f}" if r.link_n > 0 else "")


def lines(rows, words):
    """The timeline as printed: rows and words merged in time order."""
    out = []
    if rows:
        names = list(rows[0].fingers)
        out.append("     t   object x, y, z mm  sink | " + " | ".join(
            f"{n}: role asked>sensed N, tip N, up deg, round deg" if k == 0 else n
            for k, n in enumerate(names)))
    merged = [(r.t, 1, r) for r in rows] + [(t, 0, w) for t, w in words]
    for t, is_row, item in sorted(merged, key=lambda m: (m[0], m[1])):
        if is_row:
            x, y, z = item.object_mm
            sink = f"{item.sink_mm:+5.1f}" if np.isfinite(item.sink_mm) else "    -"
            out.append(f"{t:7.3f} {x:6.1f} {y:6.1f} {z:6.1f} {sink} | " +
                       " | ".join(_cell(c) for c in item.fingers.values()))
        else:
            out.append(f"{t:7.3f} -- {item}")
    return out


def _timeline_of(log, start, end, every):
    with read_run(log, "dmpl-timeline-") as (data, _, hand):
        return timeline(data, start, end, every, ContactAngles(data, hand))


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m dmpl_tools.timeline", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log", help="a run's run.lcmlog")
    ap.add_argument("--from", dest="start", type=float, required=True, help="s of sim time")
    ap.add_argument("--to", dest="end", type=float, help="s of sim time (default: --from + 1)")
    ap.add_argument("--every", type=float, default=EVERY_S, help="s between rows (at least)")
    ap.add_argument("--json", help="write the rows as JSON here")
    args = ap.parse_args(argv)
    end = args.start + 1.0 if args.end is None else args.end
    if not end > args.start:
        ap.error(f"--to ({end}) must be after --from ({args.start})")
    if not args.every > 0:
        ap.error(f"--every must be a positive number of seconds, not {args.every}")
    try:
        rows, words = _timeline_of(args.log, args.start, end, args.every)
    except LogError as e:
        print(f"timeline: {args.log}: {e}", file=sys.stderr)
        return 2
    if not rows:
        print(f"timeline: {args.log}: no rows of the truth between {args.start} and {end} s",
              file=sys.stderr)
        return 2
    print("\n".join(lines(rows, words)))
    if args.json and not write_rows(args.json, [(args.log, r) for r in rows], "timeline"):
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
