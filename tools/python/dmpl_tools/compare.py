"""Sweeps side by side: one row per case, one column per sweep (an arm: the same cases and seeds
with another setting), each trial's outcome in it, and where an arm ran every trial of a case
exactly as the first did ("="), a lever that did not act there.

    tools/dmpl compare OUT_AS_IS OUT_LEVER [...] [--names "as is,lever"] [--json FILE]

Each OUT is a `tools/dmpl sweep` output directory (its sweep.json). A case of goal orientations
shows the goals each seed reached, their sum and the median over the runs of each run's median
seconds per goal; a turn shows how many seeds succeeded, the angle each turned and the median
rate. Trials that errored are counted as such, with their reason in the JSON. Only the seeds an
arm shares with the first are set beside it (all of its own where the first did not run the
case); a case an arm did not run is "-".
"""
import argparse
import json
import statistics
import sys
from pathlib import Path


class CompareError(Exception):
    """A sweep that cannot be read: one message."""


def load_sweep(path):
    """{case: {seed: summary}} of a sweep output directory (or its sweep.json)."""
    path = Path(path)
    file = path / "sweep.json" if path.is_dir() else path
    try:
        data = json.loads(file.read_text())
    except OSError as e:
        raise CompareError(f"cannot read '{file}': {e.strerror or e}") from None
    except json.JSONDecodeError as e:
        raise CompareError(f"'{file}' is not JSON: {e}") from None
    rows = data.get("summaries") if isinstance(data, dict) else None
    if not isinstance(rows, list):
        raise CompareError(f"'{file}' is not a sweep's output (no 'summaries')")
    cases = {}
    for row in rows:
        if not isinstance(row, dict) or "seed" not in row:
            raise CompareError(f"'{file}': a summary without a seed")
        cases.setdefault(str(row.get("case") or "(all)"), {})[int(row["seed"])] = row
    return cases


def _same(a, b):
    """Whether two trials ended the same way (the outcome a lever could change)."""
    keys = ("status", "goals_reached", "rotation_total_rad", "sim_time_s", "recoveries")
    return all(a.get(k) == b.get(k) for k in keys)


def _median(values):
    values = [v for v in values if isinstance(v, (int, float))]
    return statistics.median(values) if values else None


def cell(trials):
    """What an arm's trials of one case (seed-ordered summaries) add up to."""
    errors = [t for t in trials if t.get("status") == "error"]
    runs = [t for t in trials if t.get("status") != "error"]
    out = {"seeds": [int(t["seed"]) for t in trials], "errors": len(errors),
           "error_reasons": [" ".join(map(str, t.get("problems") or [])) for t in errors]}
    if any(t.get("goals_reached") is not None for t in runs):
        goals = [int(t.get("goals_reached") or 0) for t in runs]
        out.update(kind="goals", goals=goals, goals_total=sum(goals),
                   time_per_goal_median_s=_median(t.get("time_per_goal_median_s") for t in runs))
    else:
        out.update(kind="turn", succeeded=sum(t.get("status") == "success" for t in runs),
                   runs=len(runs),
                   rotation_rad=[float(t.get("rotation_total_rad") or 0.0) for t in runs],
                   rate_median_rad_s=_median(t.get("rotation_rate_rad_s") for t in runs
                                             if t.get("status") == "success"))
    return out


def text(c):
    """A cell in Markdown."""
    if c["kind"] == "goals":
        s = f"{c['goals_total']} ({', '.join(map(str, c['goals']))})"
        if c["time_per_goal_median_s"] is not None:
            s += f", {c['time_per_goal_median_s']:.2f} s/goal"
    else:
        s = f"{c['succeeded']}/{c['runs']} ({', '.join(f'{r:.1f}' for r in c['rotation_rad'])})"
        if c["rate_median_rad_s"] is not None:
            s += f", {c['rate_median_rad_s']:.2f} rad/s"
    if c["errors"]:
        s += f", {c['errors']} errored"
    return s


def compare(sweeps):
    """{case: [cell or None per arm]} and, per case and arm, whether it ran as the first."""
    order = []
    for sweep in sweeps:
        order += [case for case in sweep if case not in order]
    table = {}
    for case in order:
        first = sweeps[0].get(case, {})
        row = []
        for k, sweep in enumerate(sweeps):
            trials = sweep.get(case, {})
            seeds = sorted(trials) if k == 0 or not first else sorted(set(trials) & set(first))
            if not seeds:
                row.append(None)
                continue
            c = cell([trials[s] for s in seeds])
            c["as_first"] = k > 0 and bool(first) and all(_same(trials[s], first[s])
                                                         for s in seeds)
            row.append(c)
        table[case] = row
    return table


def markdown(table, names):
    lines = ["| case | " + " | ".join(names) + " |", "| --- |" + " --- |" * len(names)]
    for case, row in table.items():
        cells = ["-" if c is None else ("=" if c["as_first"] else text(c)) for c in row]
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(prog="tools/dmpl compare", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("sweeps", nargs="+", help="sweep output directories, the first the baseline")
    p.add_argument("--names", help="the arms' names, comma-separated (default: the directories')")
    p.add_argument("--json", help="write the comparison here")
    a = p.parse_args(argv)
    names = [n.strip() for n in a.names.split(",")] if a.names else \
        [Path(s).name for s in a.sweeps]
    if len(names) != len(a.sweeps):
        p.error(f"--names gives {len(names)} names for {len(a.sweeps)} sweeps")
    try:
        table = compare([load_sweep(s) for s in a.sweeps])
    except CompareError as e:
        print(f"compare: {e}", file=sys.stderr)
        return 2
    print(markdown(table, names))
    if a.json:
        try:
            Path(a.json).write_text(json.dumps({"arms": names, "sweeps": a.sweeps,
                                                "cases": table}, indent=1) + "\n")
        except OSError as e:
            print(f"compare: cannot write '{a.json}': {e.strerror or e}", file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
