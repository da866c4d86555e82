"""tools/dmpl report LOG [--out DIR]: a report with the plots a reader of the paper expects.

  fig8a_orientation.png   object rotation about the task axis over time, truth against target
  fig8b_position.png      noisy (sensed) against true object position
  fig9_exploration.png    exploring fingers' force against the force asked of them
  fig10_forces.png        contact forces of all four fingers, the finger roles shaded
  statechart.png          the grasp and regrasp statecharts' states over time
  goals.png               with goal orientations: the angle to the current goal, goals reached
  replay.html             the run in 3-D, one self-contained page (tools/dmpl view)
  report.md               the headline numbers and the figures

The summary comes from DIR/summary.json when the log belongs to a run directory, else it is
computed from the log itself. The log is read in one pass, only the channels and fields the plots
need (logdata.py); a log of any record policy but none will do (an analysis log has the truth at
100 Hz, the sensed channel at 50 Hz and the controller's 100 Hz report: the same plots).
"""
import argparse
import json
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from dmpl import controller_event_t

from . import channels, experiment, faces, losses, metrics, surface
from .logdata import (Columns, LogData, LogError, angle_between, extract, cumulative_rotation, quat_conj,
                      quat_mul, rotation_vector, task_axis)

# What the plots read: the metrics' columns, the sensed object pose, the planned grip force and
# the controller's events (slips).
_CONTROLLER = ["utime", "seq", "role", "desired_force", "grip_force_n", "events/.*",
               "observed_friction", "observed_weight_n",
               *faces.CONTROLLER_FIELDS]
FIELDS = {**metrics.COLUMNS,
          channels.SENSORS_TRUE: sorted(set(metrics.COLUMNS[channels.SENSORS_TRUE]) |
                                        set(faces.TRUTH_FIELDS)),
          channels.SENSORS: ["utime", "seq", "object_position", "object_orientation",
                             "object_valid"],
          channels.CONTROLLER_STATUS: _CONTROLLER, channels.CONTROLLER_REPORT: _CONTROLLER}

ROLE_COLOURS = {1: None, 2: "#ffb74d", 0: "#cfd8dc"}  # grip: none, explore: orange, free: grey
FINGER_COLOURS = ["#1f77b4", "#2ca02c", "#d62728", "#9467bd"]


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def thin(t, y, bins=2000):
    """At most 2 * bins points of a long series, keeping each bin's lowest and highest value in
    time order: the line drawn is the same (every peak and dip stays), at a fraction of the cost
    (a 2-minute run has 124 000 ticks for a plot ~900 pixels wide)."""
    n = len(t)
    if n <= 2 * bins:
        return t, y
    k = -(-n // bins)
    pad = k * bins - n
    yy = np.concatenate([y, np.repeat(y[-1:], pad)]) if pad else y
    rows = np.nan_to_num(yy, nan=0.0).reshape(bins, k)
    base = np.arange(bins)[:, None] * k
    pick = np.sort(np.stack([rows.argmin(axis=1), rows.argmax(axis=1)], axis=1) + base, axis=1)
    idx = np.unique(np.minimum(pick.ravel(), n - 1))
    return t[idx], y[idx]


def _commanded_rotation(data, axis, t):
    """The commanded object rotation about `axis` (from the task targets), on times t."""
    tasks = data.tasks
    if not len(tasks) or not tasks["has_target"].any():
        return None
    q0 = data.object["orientation"][0]
    targets = tasks["orientation"]
    rel = rotation_vector(quat_mul(targets, quat_conj(np.repeat(q0[None], len(targets), 0))))
    angle = rel @ axis
    idx = np.clip(np.searchsorted(tasks.t, t, side="right") - 1, 0, len(tasks) - 1)
    out = angle[idx]
    out[t < tasks.t[0]] = np.nan
    out[~tasks["has_target"][idx]] = np.nan
    return out


def plot_goals(data, tolerance, path):
    """The true orientation's angle to the current goal, each reached goal marked."""
    plt = _plt()
    sup, o = data.supervisor, data.object
    sel = sup["has_orientation_goal"]
    idx = np.clip(np.searchsorted(sup.t, o.t, side="right") - 1, 0, len(sup) - 1)
    active = sel[idx] & (o.t >= sup.t[sel][0])
    error = np.full(len(o.t), np.nan)
    error[active] = angle_between(sup["orientation_goal"][idx][active], o["orientation"][active])
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(*thin(o.t, error), color="#d62728", label="angle to the current goal (truth)")
    reached = np.nonzero(np.diff(sup["goals_reached"]) > 0)[0] + 1
    for k, i in enumerate(reached):
        ax.axvline(sup.t[i], color="#2ca02c", alpha=0.5, lw=1,
                   label="goal reached" if k == 0 else None)
    ax.axhline(tolerance, color="#7f7f7f", ls=":", label=f"tolerance {tolerance:.2g} rad")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("angle to goal (rad)")
    ax.set_title(f"Goal orientations: {int(sup['goals_reached'][-1])} reached")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_orientation(data, axis_name, axis, path):
    plt = _plt()
    o = data.object
    rot = cumulative_rotation(o["orientation"], axis)
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(*thin(o.t, rot), label="object (truth)", color="#d62728")
    cmd = _commanded_rotation(data, axis, o.t)
    if cmd is not None:
        # Wrap the commanded angle onto the unwrapped truth (targets are absolute orientations).
        cmd = rot + np.angle(np.exp(1j * (cmd - rot)))
        ax.plot(*thin(o.t, cmd), "--", label="target", color="#1f77b4")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"rotation about {axis_name} (rad)")
    ax.set_title("Object orientation (Fig. 8a)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_position(data, path):
    plt = _plt()
    fig, axes = plt.subplots(3, 1, figsize=(8, 6), sharex=True)
    truth, sensed = data.object, data.object_sensed
    for i, name in enumerate("xyz"):
        ax = axes[i]
        if len(sensed):
            ax.plot(*thin(sensed.t, sensed["position"][:, i] * 1000), color="#1f77b4", lw=0.5,
                    label="sensed (noisy)")
        ax.plot(*thin(truth.t, truth["position"][:, i] * 1000), color="#d62728", lw=1.2,
                label="truth")
        ax.set_ylabel(f"{name} (mm)")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right")
    axes[0].set_title("Object position, sensed against true (Fig. 8b)")
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _roles(data, times):
    ctl = data.controller
    if not len(ctl):
        return np.ones((len(times), len(data.fingers)), dtype=int)
    idx = np.clip(np.searchsorted(ctl.t, times, side="right") - 1, 0, len(ctl) - 1)
    return ctl["role"][idx]


def plot_exploration(data, path):
    plt = _plt()
    tact = data.tactile
    fig, ax = plt.subplots(figsize=(8, 3.5))
    roles = _roles(data, tact.t)
    shown = False
    if len(data.controller):
        idx = np.clip(np.searchsorted(data.controller.t, tact.t, side="right") - 1, 0,
                      len(data.controller) - 1)
        desired = data.controller["desired_force"][idx]
        for f, name in enumerate(data.fingers):
            mask = roles[:, f] == 2
            if not mask.any():
                continue
            shown = True
            force = np.where(mask, tact["force"][:, f], np.nan)
            ax.plot(tact.t, force, color=FINGER_COLOURS[f], lw=0.8, label=f"{name} force")
            ax.plot(tact.t, np.where(mask, desired[:, f], np.nan), "--", color=FINGER_COLOURS[f],
                    lw=1.0, label=f"{name} asked")
    if not shown:
        ax.text(0.5, 0.5, "no finger explored in this run", ha="center", va="center",
                transform=ax.transAxes)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("normal force (N)")
    ax.set_title("Exploration finger force (Fig. 9)")
    ax.grid(alpha=0.3)
    if shown:
        ax.legend(loc="upper right", ncol=2, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_forces(data, path):
    plt = _plt()
    tact = data.tactile
    n = len(data.fingers)
    fig, axes = plt.subplots(n, 1, figsize=(8, 1.6 * n + 1), sharex=True, sharey=True)
    roles = _roles(data, tact.t)
    labelled = set()  # the link-contact labels given (on the first finger that has each)
    for f, name in enumerate(data.fingers):
        ax = axes[f]
        for role, colour in ROLE_COLOURS.items():
            if colour is None:
                continue
            ax.fill_between(tact.t, 0, 1, where=roles[:, f] == role, color=colour, alpha=0.5,
                            transform=ax.get_xaxis_transform(), lw=0,
                            label={2: "explore", 0: "free"}[role] if f == 0 else None)
        ax.plot(*thin(tact.t, tact["force"][:, f]), color=FINGER_COLOURS[f], lw=0.7)
        ctl = data.controller
        if len(ctl) and np.isfinite(ctl["grip_force"]).any():
            ax.plot(*thin(ctl.t, ctl["grip_force"]), ":", color="#555555", lw=0.9,
                    label="grip force planned" if f == 0 else None)
        for k, (t_event, kind, _, _) in enumerate(e for e in ctl["events"] if e[1] == controller_event_t.SLIP):
            ax.axvline(t_event, color="#d62728", lw=0.8,
                       label="slip detected" if f == 0 and k == 0 else None)
        _plot_link_contacts(ax, data, f, name, labelled)
        ax.set_ylabel(f"{name} (N)")
        ax.grid(alpha=0.3)
    axes[0].set_title("Contact forces, finger roles shaded, the grip planned for the load, "
                      "links on the object (Fig. 10)")
    handles, labels = [], []
    for ax in axes:  # one legend with every kind, wherever it first appears
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    axes[0].legend(handles, labels, loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _plot_link_contacts(ax, data, f, name, labelled):
    """Finger f's links (not its tip) on the object: the simulator's force (truth) and where the
    controller inferred a link contact from the joints' efforts (LINK_CONTACT), with how long it
    lasted (until LINK_RELEASED; logs older than that event show the onsets alone)."""
    tact = data.tactile
    link = tact["link_force"][:, f]
    if np.isfinite(link).any() and (link > 0).any():
        ax.plot(*thin(tact.t, link), "--", color="#000000", lw=0.7,
                label=_once("force on its links (truth)", labelled))
    found = [e[0] for e in data.controller["events"]
             if e[1] == controller_event_t.LINK_CONTACT and e[2] == name]
    if found:
        ax.plot(found, np.full(len(found), 0.95), "v", color="#000000", ms=3,
                transform=ax.get_xaxis_transform(),
                label=_once("link contact inferred", labelled))
    spans = link_contact_spans(data.controller["events"], name, tact.t[-1] if len(tact.t) else 0.0)
    if spans:
        starts, ends = zip(*spans)
        ax.hlines(np.full(len(spans), 0.95), starts, ends, color="#000000", lw=1.5,
                  transform=ax.get_xaxis_transform(),
                  label=_once("link contact inferred, while it lasts", labelled))


def link_contact_spans(events, name, end_s):
    """Finger `name`'s inferred link contacts as (from, to) times: each LINK_CONTACT to the next
    LINK_RELEASED, the last one to `end_s`. Empty when the log has no LINK_RELEASED for it."""
    spans, since, released = [], None, False
    for t, kind, finger, *_ in sorted(events, key=lambda e: e[0]):
        if finger != name:
            continue
        if kind == controller_event_t.LINK_CONTACT and since is None:
            since = t
        elif kind == controller_event_t.LINK_RELEASED:
            released = True
            if since is not None:
                spans.append((since, t))
                since = None
    if not released:
        return []
    if since is not None:
        spans.append((since, end_s))
    return spans


def _once(label, labelled):
    """`label` the first time it is asked for, then None (one legend entry per kind)."""
    if label in labelled:
        return None
    labelled.add(label)
    return label


def plot_states(data, path):
    plt = _plt()
    sup = data.supervisor
    fig, axes = plt.subplots(2, 1, figsize=(8, 4), sharex=True)
    if not len(sup):
        for ax in axes:
            ax.text(0.5, 0.5, "no supervisor in this run", ha="center", va="center",
                    transform=ax.transAxes)
    else:
        for ax, key, title in ((axes[0], "grasp_state", "grasp chart (Fig. 5)"),
                               (axes[1], "regrasp_state", "regrasp chart (Fig. 4)")):
            states = sup[key]
            names = list(dict.fromkeys(states))
            if key == "regrasp_state":
                names = sorted(names)
            y = [names.index(s) for s in states]
            ax.step(sup.t, y, where="post", color="#1f77b4")
            ax.set_yticks(range(len(names)))
            ax.set_yticklabels(names, fontsize=8)
            ax.set_title(title, fontsize=10)
            ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


FIGURES = [("fig8a_orientation.png", "Object orientation against its target (Fig. 8a)"),
           ("fig8b_position.png", "Sensed (noisy) against true object position (Fig. 8b)"),
           ("fig9_exploration.png", "Exploration finger force (Fig. 9)"),
           ("fig10_forces.png", "Contact forces with the finger roles shaded, and the fingers' "
                                "links on the object (Fig. 10)"),
           ("statechart.png", "Statechart states over time")]
SURFACE_FIGURE = ("surface.png", "The object's surface as the hand felt it (the supervisor's "
                                  "model, object frame) against its true shape")
GOALS_FIGURE = ("goals.png", "Angle to the current goal orientation, goals reached marked")
FACES_FIGURE = ("faces.png", "The face each finger touches, detected by touch against true")

HEADLINE = ["status", "engine", "object_shape", "object_mass_kg", "seed", "sim_time_s", "realtime_factor",
            "object_dropped", "rotation_total_rad", "final_orientation_error_rad",
            "max_position_drift_m", "grip_force_total_n", "contacts_lost", "regrasps", "recoveries",
            "max_tracking_error_rad", "exploration_force_mean_n", "exploration_force_rms_error_n",
            "rotation_rate_rad_s", "goals_reached", "time_per_goal_median_s",
            "time_per_goal_p90_s", "link_contact_s"]


def name_of(config, log_path):
    return config.get("experiment", {}).get("name", Path(log_path).stem)


def _plot_surface(log_path, config, name, out, figures):
    """The surface the supervisor learned by touch (surface.py), as a figure when it can be
    drawn; returns what it says (or why not)."""
    try:
        note = surface.plot(surface.learned(log_path), config.get("object", {}),
                            out / SURFACE_FIGURE[0], name)
    except surface.SurfaceError as e:
        return f"not drawn ({e})"
    figures.append(SURFACE_FIGURE)
    return note


def _read(log_path, obj):
    """The run's data, and the faces its fingers touched (faces.py; None without faces)."""
    if not Path(log_path).is_file():
        raise LogError(f"no such log '{log_path}'")
    with tempfile.TemporaryDirectory(prefix="dmpl-report-") as tmp:
        extract(log_path, tmp, FIELDS)
        data = LogData(Columns(tmp))
        return data, faces.faces_over_time(data, obj)


MAX_RECOVERY_ROWS = 30


def recovery_lines(data, link_n):
    """The report's lines on why each recovery began (losses.py; the contact angles are
    `tools/dmpl losses`'s): a table, at most MAX_RECOVERY_ROWS rows, and the count by cause."""
    if losses.missing_channels(data):
        return []
    recs = losses.recoveries(data, link_n)
    if not recs:
        return []
    lines = ["## Why each recovery began", "",
             "| t (s) | finger | cause (truth) | during | after (s) | link force (N) | recovered |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in recs[:MAX_RECOVERY_ROWS]:
        link = "" if np.isnan(r.link_force_n) else f"{r.link_force_n:.2f}"
        lines.append(f"| {r.t:.2f} | {r.finger or '-'} | {r.cause} | {r.action} | "
                     f"{r.into_phase_s:.2f} | {link} | {'yes' if r.recovered else 'no'} |")
    if len(recs) > MAX_RECOVERY_ROWS:
        lines.append(f"| ... | {len(recs) - MAX_RECOVERY_ROWS} more | | | | | |")
    counts = losses.tally(recs)
    lines += ["", "By cause: " + "; ".join(f"{cause} during {phase}: {n}"
                                          for (cause, phase), n in counts.most_common()), ""]
    return lines


def observed_lines(data, config):
    """What the controller observed of the object by the run's end, beside the truth."""
    ctl, obj = data.controller, config.get("object", {})
    if not len(ctl):
        return []
    gravity = float(np.linalg.norm(config.get("sim", {}).get("gravity", [0, 0, -9.81])))
    rows = []
    for key, label, unit, truth in (
            ("observed_weight", "weight the tips carry", " N",
             obj.get("mass") and float(obj["mass"]) * gravity),
            ("observed_friction", "friction the explorers' slides show", "",
             obj.get("friction"))):
        v = float(ctl[key][-1])
        seen = f"{v:.3g}{unit}" if np.isfinite(v) and v > 0 else "not observed"
        of = f" (the object's: {float(truth):.3g}{unit})" if truth else ""
        rows.append(f"| {label} | {seen}{of} |")
    return rows


def make_report(log_path, out_dir=None, summary=None, config=None, replay_path=None):
    """Writes the figures, report.md and a 3-D replay (replay_path, default OUT/replay.html;
    False: none); returns the report's path."""
    log_path = Path(log_path)
    out = Path(out_dir) if out_dir else log_path.parent / "report"
    out.mkdir(parents=True, exist_ok=True)
    run_dir = log_path.parent
    if config is None and (run_dir / "config.yaml").exists():
        config = experiment.load_yaml(run_dir / "config.yaml")
    config = config or {}
    config.setdefault("metrics", {})
    for k, v in experiment.METRICS_DEFAULTS.items():
        config["metrics"].setdefault(k, v)
    if summary is None and (run_dir / "summary.json").exists():
        summary = json.loads((run_dir / "summary.json").read_text())
    data, touched = _read(log_path, config.get("object", {}))
    if summary is None:
        summary = metrics.compute(data, config)
    if data.problems:  # what this pass over the log could not read (beside the run's own)
        summary = dict(summary, warnings=[*summary.get("warnings", []),
                                          *(f"reading the log: {p}" for p in data.problems)])
    plot_orientation(data, *task_axis(config), out / FIGURES[0][0])
    figures = list(FIGURES)
    if len(data.supervisor) and data.supervisor["has_orientation_goal"].any():
        tolerance = float(config.get("task", {}).get("goal_tolerance_rad", 0.4))
        plot_goals(data, tolerance, out / GOALS_FIGURE[0])
        figures.append(GOALS_FIGURE)
    plot_position(data, out / FIGURES[1][0])
    plot_exploration(data, out / FIGURES[2][0])
    plot_forces(data, out / FIGURES[3][0])
    plot_states(data, out / FIGURES[4][0])
    surface_note = _plot_surface(log_path, config, name_of(config, log_path), out, figures)
    faces_note = None
    if touched is not None:
        faces.plot(touched, data.fingers, out / FACES_FIGURE[0], _plt())
        figures.append(FACES_FIGURE)
        faces_note = f"{100 * faces.agreement(touched):.0f} % of the contact time"
    name = name_of(config, log_path)
    lines = [f"# dmpl report: {name}", "", f"Log: `{log_path}`", "", "| metric | value |",
             "| --- | --- |"]
    for key in HEADLINE:
        if key in summary:
            v = summary[key]
            lines.append(f"| {key} | {v:.4g} |" if isinstance(v, float) else f"| {key} | {v} |")
    lines.append(f"| surface felt | {surface_note} |")
    lines += observed_lines(data, config)
    if faces_note:
        lines.append(f"| face detected = true face | {faces_note} |")
    for p in summary.get("problems", []):
        lines.append(f"| problem | {p} |")
    for w in summary.get("warnings", []):
        lines.append(f"| warning | {w} |")
    replay = _write_replay(log_path, out, replay_path)
    if isinstance(replay, Path):
        lines += ["", f"3-D replay (opens offline in a browser): "
                      f"[{replay.name}]({os.path.relpath(replay, out)})"]
    elif replay:
        lines += ["", f"3-D replay: not written ({replay})"]
    lines.append("")
    lines += recovery_lines(data, float(config["metrics"]["link_contact_n"]))
    for file, caption in figures:
        lines += [f"## {caption}", "", f"![{caption}]({file})", ""]
    report = out / "report.md"
    report.write_text("\n".join(lines))
    return report


def _write_replay(log_path, out, replay_path):
    """The replay's path, or why there is none (the report stands without it)."""
    if replay_path is False:
        return None
    from . import view
    path = Path(replay_path) if replay_path else out / "replay.html"
    try:
        path.unlink(missing_ok=True)  # never a stale replay of another run
        return view.write_replay(log_path, path)
    except (view.ViewError, LogError, OSError, RuntimeError) as e:
        return str(e)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl report", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log", help="an LCM log recorded by tools/dmpl run or launch")
    ap.add_argument("--out", help="output directory (default: LOG's directory/report)")
    args = ap.parse_args(argv)
    if not Path(args.log).is_file():
        print(f"dmpl report: no such log '{args.log}'", file=sys.stderr)
        return 2
    try:
        report = make_report(args.log, args.out)
    except (LogError, experiment.ExperimentError, OSError) as e:
        print(f"dmpl report: {e}", file=sys.stderr)
        return 2
    print(f"report: {report}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
