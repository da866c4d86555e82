"""What the hand learned of the object's surface by touch in a recorded run: the supervisor's own
model (C++, `dmpl_surface`, the same Blackboard::LearnSurface the gait planned on), drawn in the
object's frame against the true shape of the run's config (for display only: nothing of the
object's shape reaches the controller or the supervisor).

  tools/dmpl surface RUN/run.lcmlog [--out FIGURE.png]
"""
import argparse
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from . import experiment
from .paths import executable


class SurfaceError(Exception):
    pass


def learned(log_path, directions=400):
    """dmpl_surface's JSON for a log: contacts (object frame) and the surface along directions."""
    try:
        cmd = [executable("dmpl_surface"), str(log_path), "--directions", str(directions)]
    except FileNotFoundError as e:
        raise SurfaceError(str(e)) from None
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise SurfaceError(done.stderr.strip() or f"dmpl_surface failed ({done.returncode})")
    return json.loads(done.stdout)


def true_distance(obj, d):
    """How far the true surface of the config's object lies from its centre along unit d (object
    frame; Bullet's cylinders and capsules along z)."""
    shape, r = obj.get("shape", "sphere"), float(obj.get("radius", 0.025))
    d = np.asarray(d, dtype=float)
    if shape == "ellipsoid":
        a = np.asarray(obj.get("radii", [r, r, r]), dtype=float)
        return 1.0 / np.sqrt(((d / a) ** 2).sum())
    if shape == "box":
        half = np.asarray(obj.get("size", [0.05] * 3), dtype=float) / 2
        return min(h / abs(c) for h, c in zip(half, d) if abs(c) > 1e-12)
    if shape in ("cylinder", "capsule"):
        h = float(obj.get("length", 0.09)) / 2
        side = r / max(np.hypot(d[0], d[1]), 1e-12)
        if shape == "cylinder":
            return min(side, h / max(abs(d[2]), 1e-12))
        if abs(d[2]) * side <= h:
            return side
        # The cap: a sphere of radius r at z = +-h.
        c = np.array([0.0, 0.0, np.sign(d[2]) * h])
        b = d @ c
        return b + np.sqrt(max(b * b - c @ c + r * r, 0.0))
    return r


def plot(model, obj, path, title=""):
    """Three sections through the object's centre (the planes of its frame): the contacts kept
    near each plane, the model's surface along the plane's directions (known and not), the true
    shape's outline."""
    from .report import _plt
    plt = _plt()
    contacts = np.array([c["point"] for c in model["contacts"]]).reshape(-1, 3)
    fig, axes = plt.subplots(1, 3, figsize=(11, 4))
    angles = np.linspace(0, 2 * np.pi, 181)
    for ax, (i, j, k) in zip(axes, [(0, 1, 2), (0, 2, 1), (1, 2, 0)]):
        names = "xyz"
        plane = np.zeros((len(angles), 3))
        plane[:, i], plane[:, j] = np.cos(angles), np.sin(angles)
        truth = np.array([true_distance(obj, d) for d in plane])
        ax.plot(truth * plane[:, i] * 100, truth * plane[:, j] * 100, color="#9e9e9e", lw=2,
                label="true shape (config)")
        along = [a for a in model["along"] if abs(a["direction"][k]) < 0.15]
        for known, style in ((True, "o"), (False, "x")):
            pts = np.array([np.array(a["direction"]) * a["distance_m"] for a in along
                            if a["known"] == known and a["distance_m"] > 0]).reshape(-1, 3)
            ax.plot(pts[:, i] * 100, pts[:, j] * 100, style, ms=3,
                    color="#1565c0" if known else "#ef6c00",
                    label="model: felt" if known else "model: too little felt")
        near = contacts[np.abs(contacts[:, k]) < 0.004] if len(contacts) else contacts
        ax.plot(near[:, i] * 100, near[:, j] * 100, ".", ms=2, color="#000000",
                label="contacts kept (within 4 mm)")
        ax.set_xlabel(f"{names[i]} (cm)")
        ax.set_ylabel(f"{names[j]} (cm)")
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="upper left")
    errors = [abs(a["distance_m"] - true_distance(obj, a["direction"])) for a in model["along"]
              if a["known"]]
    summary = (f"{len(model['contacts'])} contacts kept; surface known along {len(errors)} of "
               f"{len(model['along'])} directions")
    if errors:
        summary += f", median error {np.median(errors) * 1000:.1f} mm"
    fig.suptitle(f"{title}: the surface felt (object frame). {summary}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return summary


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl surface", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log", help="a run's log (RUN/run.lcmlog)")
    ap.add_argument("--out", help="the figure (default: RUN/surface.png)")
    args = ap.parse_args(argv)
    log = Path(args.log)
    if not log.is_file():
        print(f"dmpl surface: no such log '{log}'", file=sys.stderr)
        return 2
    try:
        config = experiment.load_yaml(log.parent / "config.yaml")
        model = learned(log)
    except (SurfaceError, OSError, ValueError, experiment.ExperimentError) as e:
        print(f"dmpl surface: {e}", file=sys.stderr)
        return 2
    out = Path(args.out) if args.out else log.parent / "surface.png"
    print(plot(model, config.get("object", {}), out, config.get("experiment", {}).get("name", "")))
    print(f"dmpl surface: {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
