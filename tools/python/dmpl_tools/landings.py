"""Where each explorer landed, and what followed: the contact's angle round the tip before and
after the explore, how far the surface there faces off the direction from the object's centre,
and whether a link of that finger took the load soon after.

    python -m dmpl_tools.landings RUN/run.lcmlog [RUN2/run.lcmlog ...] [--within S] [--json FILE]
    tools/dmpl landings out/sweeps/NAME/*/seed*/run.lcmlog   # a sweep run with --record analysis

The gait sends an explorer to its home turned about the sensed centre: on a sphere the surface
there faces straight out from the centre, as it did at the home, and the tip meets it as it met
it there. Elsewhere the surface faces off that direction (its tilt: up to 30 deg on the
3.5 x 2.5 x 2 cm ellipsoid's flanks) and the contact lands that much further round the tip or
back toward its front; past ~95 deg the distal link lies within millimetres of the surface.
Everything is the simulator's truth (the tip's axis and centre by forward kinematics of the true
joints, the true normal and object position): an analysis, never what the controller knows.
An explore is a phase of the regrasp chart whose action explores ("A4 R explore", ...) while the
grasp chart runs its tasks; it lands when that phase ends. Needs the truth at least every 10
ticks: any record policy but none.
"""
import argparse
import sys
from dataclasses import dataclass

import numpy as np

from . import experiment
from .logdata import LogError
from .losses import ContactAngles, index_at, read_run, write_rows
from .phases import kind, phases

WITHIN_S = 1.0  # a link taking the load this soon after a landing is counted against it
# A contact read this near an explore's start or end is its own: a soft contact (MuJoCo's)
# flickers for a few ticks as a tip settles or lets go.
SETTLE_S = 0.05


@dataclass
class Landing:
    t: float                # s: the explore ended
    finger: str
    angle_before_deg: float  # round the tip from its front as the explore began; NaN: no contact
    angle_after_deg: float   # the same as it landed; NaN: no contact then
    tilt_deg: float          # the surface's normal there against the direction from the centre
    on_sphere_deg: float     # the angle it would have landed at on a sphere about that centre
    link_after_s: float      # s from landing until a link of the finger took the load; NaN: none


class SurfaceTilt:
    """At a row of the truth, finger f's tip against the object (deg): `tilt` how far the
    surface's normal at its contact faces off the direction from the object's centre to the tip's
    centre (0 on a sphere), `on_sphere` the contact angle the tip would have there on a sphere
    about the same centre (its axis against the direction to the centre)."""

    def __init__(self, data, hand):
        self.angles = ContactAngles(data, hand)
        self.positions = data.object["position"]

    def _tip_and_out(self, f, i):
        a = self.angles
        if a.hand is None or a.q is None or not a.names:
            return None, None
        tip = a.hand.link_poses(dict(zip(a.names, a.q[i]))).get(a.fingers[f] + "_tip")
        if tip is None:
            return None, None
        out = tip[:3, 3] - np.asarray(self.positions[i], dtype=float)
        n = np.linalg.norm(out)
        return (tip, out / n) if n > 1e-9 else (None, None)

    def tilt(self, f, i):
        tip, out = self._tip_and_out(f, i)
        normals = self.angles.normals
        if tip is None or normals is None:
            return float("nan")
        normal = np.asarray(normals[i][f], dtype=float)  # from the object into the tip: out of it
        if not np.linalg.norm(normal) > 0.5:
            return float("nan")
        cosine = normal @ out / np.linalg.norm(normal)
        return float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))

    def on_sphere(self, f, i):
        tip, out = self._tip_and_out(f, i)
        if tip is None:
            return float("nan")
        return float(np.degrees(np.arccos(np.clip(tip[:3, 2] @ -out, -1.0, 1.0))))


def _touching_row(t, touching, t0, t1, last):
    """The last (or first) row in [t0, t1] at which the finger touched; when the window holds
    none (truth sparser than it), the row at or just before t1 (or t0) if the finger touched
    there; else None."""
    rows = np.flatnonzero((t >= t0 - 1e-9) & (t <= t1 + 1e-9) & touching)
    if len(rows):
        return int(rows[-1] if last else rows[0])
    row = index_at(t, t1 if last else t0)
    return row if touching[row] else None


def landings(data, link_n=experiment.METRICS_DEFAULTS["link_contact_n"], within=WITHIN_S,
             angle_at=None, tilt_at=None, sphere_at=None):
    """[Landing] of a LogData, in time order; `angle_at(f, truth row)` (ContactAngles),
    `tilt_at` and `sphere_at` (SurfaceTilt.tilt, .on_sphere): deg, or None for NaN."""
    nan = lambda f, i: float("nan")  # noqa: E731
    angle_at, tilt_at, sphere_at = angle_at or nan, tilt_at or nan, sphere_at or nan
    fingers = list(data.fingers)
    t = np.asarray(data.tactile.t, dtype=float)
    touching = np.asarray(data.tactile["in_contact"], dtype=bool)
    link = np.nan_to_num(np.asarray(data.tactile["link_force"], dtype=float))
    out = []
    for action, state, start, duration in phases(data):
        parts = str(action).split()
        if str(state) != "Tasks" or not kind(action).startswith("explore") or len(parts) < 2:
            continue
        if parts[1] not in fingers:
            continue
        f, end = fingers.index(parts[1]), start + duration
        before = _touching_row(t, touching[:, f], start - SETTLE_S, start, last=True)
        after = _touching_row(t, touching[:, f], end, end + SETTLE_S, last=False)
        later = (t > end) & (t <= end + within) & (link[:, f] > link_n)
        out.append(Landing(
            float(end), parts[1],
            angle_at(f, before) if before is not None else float("nan"),
            angle_at(f, after) if after is not None else float("nan"),
            tilt_at(f, after) if after is not None else float("nan"),
            sphere_at(f, after) if after is not None else float("nan"),
            float(t[later][0] - end) if later.any() else float("nan")))
    return out


def _landings_of(log, within):
    with read_run(log, "dmpl-landings-") as (data, link_n, hand):
        tilt = SurfaceTilt(data, hand)
        return landings(data, link_n, within, ContactAngles(data, hand), tilt.tilt,
                        tilt.on_sphere)


ANGLE_BINS = ((0.0, 90.0), (90.0, 100.0), (100.0, 180.0))
TILT_BINS = ((0.0, 10.0), (10.0, 20.0), (20.0, 90.0))
# What the surface's tilt did to the contact angle (landed less the sphere's angle there).
TURN_BINS = (("tilt: toward the front", -180.0, -10.0), ("tilt: within 10 deg", -10.0, 10.0),
             ("tilt: toward the link", 10.0, 180.0))


def summary_lines(found, within=WITHIN_S):
    """The landings grouped by where they landed round the tip and by the surface's tilt there:
    how many, the median change of the contact angle, and how many a link took within `within`."""
    rows = [r for r in found if not np.isnan(r.angle_after_deg)]
    lines = [f"{len(found)} landings, {len(rows)} on the object"]
    if not rows:
        return lines
    lines.append(f"{'':24s} {'landings':>8s} {'angle change':>13s} {'link within':>12s}")

    def group(name, members):
        if not members:
            return
        change = [r.angle_after_deg - r.angle_before_deg for r in members
                  if not np.isnan(r.angle_before_deg)]
        linked = sum(not np.isnan(r.link_after_s) for r in members)
        median = f"{np.median(change):+.0f} deg" if change else "-"
        lines.append(f"{name:24s} {len(members):8d} {median:>13s} "
                     f"{linked:5d} ({100.0 * linked / len(members):3.0f} %)")
    group("all", rows)
    for lo, hi in ANGLE_BINS:
        group(f"landed {lo:.0f}-{hi:.0f} deg round", [r for r in rows
                                                      if lo <= r.angle_after_deg < hi])
    for lo, hi in TILT_BINS:
        group(f"surface tilted {lo:.0f}-{hi:.0f} deg", [r for r in rows if lo <= r.tilt_deg < hi])
    for name, lo, hi in TURN_BINS:
        group(name,
              [r for r in rows if lo <= r.angle_after_deg - r.on_sphere_deg < hi])
    lines.append(f"(angle change: round the tip, from before the explore to its landing; tilt: "
                 f"the landing's angle less a sphere's there; link within: a link of the finger "
                 f"took the load within {within:.1f} s of landing)")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m dmpl_tools.landings", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("logs", nargs="+", help="runs' run.lcmlog")
    ap.add_argument("--within", type=float, default=WITHIN_S,
                    help="s after a landing in which a link taking the load counts against it")
    ap.add_argument("--json", help="write every landing as JSON here")
    ap.add_argument("--quiet", action="store_true", help="the summary only, not every landing")
    args = ap.parse_args(argv)
    if not args.within > 0:
        ap.error(f"--within must be a positive number of seconds, not {args.within}")
    every, failed = [], 0
    for log in args.logs:
        try:
            found = _landings_of(log, args.within)
        except LogError as e:
            print(f"landings: {log}: {e}", file=sys.stderr)
            failed += 1
            continue
        every += [(log, r) for r in found]
        for r in found if not args.quiet else ():
            link = "" if np.isnan(r.link_after_s) else f", link {r.link_after_s:.2f} s later"
            print(f"{log}: {r.t:7.2f} s {r.finger:2s} {r.angle_before_deg:4.0f} -> "
                  f"{r.angle_after_deg:4.0f} deg round the tip, surface tilted "
                  f"{r.tilt_deg:3.0f} deg (on a sphere: {r.on_sphere_deg:4.0f}){link}")
    if args.json and not write_rows(args.json, every, "landings"):
        failed += 1
    print("\n".join(summary_lines([r for _, r in every], args.within)))
    return 2 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
