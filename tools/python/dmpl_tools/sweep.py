"""tools/dmpl sweep CONFIG --seeds N [--jobs J] [--out DIR] [--set key=value]... [--multiprocess]
   tools/dmpl sweep --cases FILE --seeds N [...]

N trials of one experiment with seeds 1..N (or --first-seed S..), J at a time. With --cases, every
case of FILE times every seed: FILE names a base experiment and a list of named cases, each a set
of overrides (the keys of --set; see configs/benchmarks/unknown_objects.yaml), and the tables are
per case. Each trial runs in one-process mode (no sockets shared, nothing to collide);
--multiprocess runs the full process set instead, each trial on its own LCM port. Each trial's
launcher runs in a Python process of its own: one that dies (a signal, a crash of a binding) is
that trial's error row, and the sweep goes on. Writes DIR/sweep.md
(tables), DIR/sweep.json (keys `trials`, `success_rate`, `cases`, and one summary per trial),
DIR/sweep.parquet (one row per trial, for pandas and polars) and each trial's run directory
(DIR/seedN, or DIR/CASE/seedN). Trials keep no log by default (--record none: their metrics are
computed online); --record analysis or full keeps one per trial. --resume skips the trials
already finished in DIR; --cluster ADDRESS runs the trials on a Dask scheduler's workers, each
trial a one-process run that returns its summary (docs/clusters.md).
"""
import argparse
import contextlib
import importlib.metadata
import json
import os
import platform
import queue
import signal
import statistics
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from . import experiment
from .affinity import child_command
from .lcm_url import LcmUnavailable
from .process_set import RECORD_POLICIES, SetError
from .paths import OUT, ROOT
from .run import add_common_args, run_experiment, strict_json

GRAVITY = 9.81
COLUMNS = [("seed", "seed", "{}"), ("status", "status", "{}"),
           ("rotation_total_rad", "rotation (rad)", "{:.3f}"),
           ("final_orientation_error_rad", "final error (rad)", "{:.4f}"),
           ("max_position_drift_m", "drift (m)", "{:.4f}"),
           ("grip_force_total_n", "grip (N)", "{:.2f}"),
           ("grip_force_peak_n", "peak grip (N)", "{:.2f}"),
           ("contacts_lost", "contacts lost", "{}"),
           ("regrasps", "regrasps", "{}"), ("recoveries", "recoveries", "{}"),
           ("object_dropped", "dropped", "{}"),
           ("rotation_rate_rad_s", "rate (rad/s)", "{:.3f}"), ("goals_reached", "goals", "{}"),
           ("time_per_goal_median_s", "s per goal", "{:.2f}"),
           ("link_contact_s", "link touch (s)", "{:.2f}"),
           ("sim_time_s", "sim time (s)", "{:.1f}"), ("realtime_factor", "RTF", "{:.2f}"),
           ("problems", "why not a success", "{}")]


@dataclass
class Case:
    """One experiment of a sweep: a config and its overrides; `name` is None for a plain sweep."""
    name: str
    config: Path
    sets: list = field(default_factory=list)


def load_cases(path):
    """The cases of a --cases file: `base` (an experiment, relative to the file) and `cases`, a
    list of {name, set: {key: value}}. Errors name the file and the entry."""
    data = experiment.load_yaml(path)
    where = str(path)
    unknown = set(data) - {"base", "cases"}
    if unknown:
        raise experiment.ExperimentError(f"{where}: unknown keys {sorted(unknown)} (expected "
                                         "base, cases)")
    if not isinstance(data.get("base"), str):
        raise experiment.ExperimentError(f"{where}: 'base' must name an experiment file")
    base = (Path(path).parent / data["base"]).resolve()
    if not base.is_file():
        raise experiment.ExperimentError(f"{where}: base '{data['base']}' does not exist")
    entries = data.get("cases")
    if not isinstance(entries, list) or not entries:
        raise experiment.ExperimentError(f"{where}: 'cases' must be a non-empty list")
    cases, names = [], set()
    for i, entry in enumerate(entries):
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str) or \
                set(entry) - {"name", "set"} or not isinstance(entry.get("set", {}), dict):
            raise experiment.ExperimentError(f"{where}: cases[{i}] must be {{name: ..., set: "
                                             "{key: value, ...}}")
        if entry["name"] in names or "/" in entry["name"]:
            raise experiment.ExperimentError(f"{where}: cases[{i}]: name '{entry['name']}' is "
                                             "repeated or has a '/'")
        names.add(entry["name"])
        sets = [f"{k}={json.dumps(v)}" for k, v in entry.get("set", {}).items()]
        cases.append(Case(entry["name"], base, sets))
    return cases


def _cell(summary, key, fmt):
    v = summary.get(key)
    if key == "problems":  # why a trial failed or errored, in one cell
        return "; ".join(map(str, v)).replace("|", "/") if v else ""
    if v is None:
        return "-"
    try:
        return fmt.format(v)
    except (ValueError, TypeError):
        return str(v)


def _table(columns, trials):
    rows = ["| " + " | ".join(c[1] for c in columns) + " |",
            "| " + " | ".join("---" for _ in columns) + " |"]
    for s in trials:
        rows.append("| " + " | ".join(_cell(s, k, f) for k, _, f in columns) + " |")
    return rows


def case_stats(trials):
    """What a case's trials add up to: success rate, medians and extremes, drops."""
    def values(key):
        return [s[key] for s in trials if isinstance(s.get(key), (int, float))
                and not isinstance(s.get(key), bool)]
    ok = [s for s in trials if s.get("status") == "success"]
    rotation, drift, peak = values("rotation_total_rad"), values("max_position_drift_m"), \
        values("grip_force_peak_n")
    mass, rate = values("object_mass_kg"), values("rotation_rate_rad_s")
    return {"trials": len(trials), "succeeded": len(ok),
            "success_rate": len(ok) / len(trials) if trials else 0.0,
            "rotation_median_rad": statistics.median(rotation) if rotation else None,
            "rate_median_rad_s": statistics.median(rate) if rate else None,
            "drift_max_m": max(drift) if drift else None,
            "grip_force_peak_max_n": max(peak) if peak else None,
            "object_weight_n": mass[0] * GRAVITY if mass else None,
            "drops": sum(1 for s in trials if s.get("object_dropped"))}


CASE_COLUMNS = [("case", "case", "{}"), ("succeeded", "succeeded", "{}"),
                ("trials", "trials", "{}"), ("success_rate", "success", "{:.0%}"),
                ("rotation_median_rad", "rotation median (rad)", "{:.3f}"),
                ("rate_median_rad_s", "rate median (rad/s)", "{:.3f}"),
                ("drift_max_m", "drift max (m)", "{:.4f}"),
                ("grip_force_peak_max_n", "peak grip (N)", "{:.2f}"),
                ("object_weight_n", "weight (N)", "{:.3f}"), ("drops", "drops", "{}")]


def write_table(out, title, trials):
    ok = [s for s in trials if s.get("status") == "success"]
    rate = len(ok) / len(trials) if trials else 0.0
    lines = [f"# Sweep of `{title}`", "",
             f"{len(ok)} of {len(trials)} trials succeeded (success rate {rate:.0%}).", ""]
    cases = list(dict.fromkeys(s["case"] for s in trials if s.get("case")))
    per_case = {}
    if cases:
        per_case = {c: case_stats([s for s in trials if s.get("case") == c]) for c in cases}
        lines += ["## Per case", "", *_table(CASE_COLUMNS, [dict(v, case=c) for c, v in
                                                            per_case.items()]), ""]
    for key, label in (("rotation_total_rad", "rotation"), ("final_orientation_error_rad",
                                                          "final orientation error"),
                       ("rotation_rate_rad_s", "rotation rate (rad/s)"),
                       ("goals_reached", "goals reached"),
                       ("time_per_goal_median_s", "time per goal, median of a run (s)"),
                       ("realtime_factor", "real-time factor")):
        vals = [s[key] for s in trials if isinstance(s.get(key), (int, float))]
        if vals:
            lines.append(f"- {label}: median {statistics.median(vals):.4g}, "
                         f"min {min(vals):.4g}, max {max(vals):.4g}")
    columns = ([("case", "case", "{}")] if cases else []) + COLUMNS
    lines += ["", "## Trials", "", *_table(columns, trials), ""]
    (out / "sweep.md").write_text("\n".join(lines))
    doc = {"config": str(title), "trials": len(trials), "succeeded": len(ok),
           "success_rate": rate, "summaries": trials}
    if per_case:
        doc["cases"] = per_case
    (out / "sweep.json").write_text(json.dumps(strict_json(doc, []), indent=2, sort_keys=True,
                                               allow_nan=False))
    write_parquet(out / "sweep.parquet", trials)
    return rate


def write_parquet(path, trials):
    """One row per trial: every summary key a column (lists of problems joined by '; ')."""
    import pyarrow as pa
    import pyarrow.parquet as pq
    keys = sorted({k for s in trials for k in s})
    rows = [{k: "; ".join(map(str, v)) if isinstance(v, list) else v for k, v in s.items()}
            for s in trials]
    columns = {}
    for k in keys:
        values = [r.get(k) for r in rows]
        try:
            columns[k] = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed types across trials: as text
            columns[k] = pa.array([None if v is None else str(v) for v in values])
    pq.write_table(pa.table(columns), path)


def run_trial(spec):
    """One trial, from a plain dict (it may travel to a Dask worker): its summary, with `case`
    when the sweep has cases. With spec["resume"], a trial whose run directory already holds the
    summary of the same config is not run again (its summary gets `resumed: true`)."""
    run_dir = Path(spec["run_dir"])
    if spec.get("resume"):
        done = finished_trial(run_dir, spec)
        if done is not None:
            return done
    try:
        summary, _ = run_experiment(spec["config"], run_dir, seed=spec["seed"],
                                    sets=spec["sets"], params=spec["params"], lcm_url=spec["url"],
                                    echo=False, one_process=spec["one_process"],
                                    record=spec["record"], cpus=spec.get("cpus"))
    except (experiment.ExperimentError, OSError, ValueError) as e:
        # A trial that cannot run is a row that says why, not a sweep that stops.
        return _error_summary(spec, str(e))
    if spec["case"] is not None:
        summary["case"] = spec["case"]
    return summary


def _error_summary(spec, problem):
    """The row of a trial that did not run to its end, saying why."""
    summary = {"status": "error", "seed": spec["seed"], "problems": [problem]}
    if spec["case"] is not None:
        summary["case"] = spec["case"]
    return summary


def finished_trial(run_dir, spec):
    """The summary of a trial already run in `run_dir` with the config this spec resolves to
    (its run identity aside), else None: an interrupted, failed-to-write or different trial is
    run again."""
    try:
        summary = json.loads((run_dir / "summary.json").read_text())
        ran = experiment.load_yaml(run_dir / "config.yaml")
    except (OSError, ValueError, experiment.ExperimentError):
        return None
    wanted = experiment.resolve(spec["config"], spec["params"], spec["sets"], spec["seed"])
    for config in (ran, wanted):
        config.get("run", {}).pop("run_id", None)
        if config.get("run") == {}:
            del config["run"]
    if summary.get("status") == "interrupted" or ran != wanted:
        return None
    summary["resumed"] = True
    if spec["case"] is not None:
        summary["case"] = spec["case"]
    return summary


def trial_specs(config_path, seeds, out, sets=(), params=(), one_process=True, first_seed=1,
                port_base=7900, record="none", cases=None, resume=False):
    """Every trial of a sweep as a plain dict run_trial takes: every case times every seed."""
    named = cases is not None
    cases = cases or [Case(None, Path(config_path), [])]
    work = [(case, first_seed + i) for case in cases for i in range(seeds)]
    return [{"config": str(Path(case.config).resolve()), "seed": seed,
             "sets": [*case.sets, *sets], "params": [str(Path(p).resolve()) for p in params],
             "record": record, "one_process": one_process,
             "case": case.name if named else None, "resume": resume,
             "run_dir": str(out / case.name / f"seed{seed}" if named else out / f"seed{seed}"),
             "url": None if one_process else f"udpm://239.255.76.67:{port_base + i}?ttl=0"}
            for i, (case, seed) in enumerate(work)]


TRIALS_FILE = "trials.json"
SLURM_SCRIPT = """#!/bin/bash
# Written by tools/dmpl sweep --slurm-script: {n} trials of {title}, one per array task.
# Every node needs the project at {root}, built (a shared file system); the trials write to
# {out}. Submit: sbatch {script}. Gather: tools/dmpl sweep --collect {out}
#SBATCH --job-name=dmpl-sweep
#SBATCH --array=0-{last}
#SBATCH --cpus-per-task=1
#SBATCH --output={out}/slurm-%A_%a.out
set -euo pipefail
cd {root}
export PYTHONPATH={build}/python:{root}/tools/python DMPL_BUILD_DIR={build}
exec {python} -m dmpl_tools.sweep --run-trial {out}/{trials} "$SLURM_ARRAY_TASK_ID"
"""


def write_slurm_script(path, title, out, specs):
    """Writes OUT/trials.json and an `sbatch --array` script that runs trial i in array task i;
    `--collect OUT` gathers their summaries into the sweep's tables."""
    from .paths import BUILD
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    (out / TRIALS_FILE).write_text(json.dumps({"title": str(title), "trials": specs}, indent=1))
    Path(path).write_text(SLURM_SCRIPT.format(
        n=len(specs), title=title, root=ROOT, out=out, script=path, last=len(specs) - 1,
        build=BUILD, python=ROOT / ".venv" / "bin" / "python", trials=TRIALS_FILE))
    os.chmod(path, 0o755)


def run_listed_trial(trials_file, index):
    """Array task `index` of a --slurm-script sweep (resumable: a finished trial is kept)."""
    specs = json.loads(Path(trials_file).read_text())["trials"]
    if not 0 <= index < len(specs):
        raise experiment.ExperimentError(f"{trials_file}: no trial {index} (it has {len(specs)})")
    summary = run_trial(dict(specs[index], resume=True))
    print(f"[sweep] trial {index}: {summary['status']}", file=sys.stderr)
    return summary


def collect(out):
    """The sweep's tables from the summaries its trials wrote (--slurm-script); returns
    (trials, rate, missing run directories)."""
    out = Path(out)
    try:
        listed = json.loads((out / TRIALS_FILE).read_text())
    except (OSError, ValueError) as e:
        raise experiment.ExperimentError(f"--collect {out}: no readable {TRIALS_FILE} ({e}); "
                                         "it is written by --slurm-script") from None
    trials, missing = [], []
    for spec in listed["trials"]:
        try:
            summary = json.loads((Path(spec["run_dir"]) / "summary.json").read_text())
        except (OSError, ValueError):
            missing.append(spec["run_dir"])
            summary = {"status": "missing", "seed": spec["seed"]}
        if spec["case"] is not None:
            summary["case"] = spec["case"]
        trials.append(summary)
    return trials, write_table(out, listed["title"], trials), missing


def run_sweep(config_path, seeds, jobs, out, sets=(), params=(), one_process=True,
              first_seed=1, port_base=7900, record="none", cases=None, resume=False,
              cluster=None):
    """Runs every case (default: one, `config_path` with `sets`) with every seed; returns the
    trials' summaries (each with its `case` when there are cases) and the success rate.
    resume: skip the trials whose run directory holds a finished one (finished_trial).
    cluster: a Dask scheduler's address; its workers run the trials (one-process mode)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    specs = trial_specs(config_path, seeds, out, sets, params, one_process, first_seed,
                        port_base, record, cases, resume)
    named = cases is not None
    done = []

    def report(summary):
        done.append(summary)
        rotation = summary.get("rotation_total_rad")
        label = (f"{summary['case']} " if named else "") + f"seed {summary.get('seed')}"
        print(f"[sweep] {label}: {summary['status']}{' (done before)' if summary.get('resumed') else ''}"
              f", rotation {'-' if rotation is None else f'{rotation:.3f}'} rad, "
              f"{len(done)}/{len(specs)} done", file=sys.stderr, flush=True)

    if cluster:
        if not one_process:
            raise experiment.ExperimentError("--cluster runs one-process trials only")
        trials = _run_on_cluster(cluster, specs, report)
    else:
        trials = _run_here(specs, jobs, report)
    rate = write_table(out, config_path, trials)
    return trials, rate


def _run_here(specs, jobs, report):
    lock = threading.Lock()
    # With no more trials at a time than CPUs, each trial runs on a CPU of its own (a pinned
    # loop wakes its processes locally; see affinity.py); otherwise the scheduler places them.
    available = sorted(os.sched_getaffinity(0))
    pinned = jobs <= len(available)
    cpus = queue.Queue()
    for c in available:
        cpus.put(c)

    def trial(spec):
        cpu = cpus.get() if pinned else None
        try:
            summary = _trial_in_own_process(dict(spec, cpus=None if cpu is None else [cpu]))
        finally:
            if cpu is not None:
                cpus.put(cpu)
        with lock:
            report(summary)
        return summary

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(trial, spec) for spec in specs]
        try:
            return [f.result() for f in futures]
        except KeyboardInterrupt:
            for f in futures:
                f.cancel()
            # Each trial's process stops its set on the interrupt (a terminal's Ctrl-C reaches
            # them already; a `kill -INT` of the sweep alone does not).
            with _TRIALS_LOCK:
                for child in list(_TRIAL_PROCESSES):
                    if child.poll() is None:
                        child.send_signal(signal.SIGINT)
            raise


WORKER_WAIT_S = 30


_TRIAL_PROCESSES = set()  # the trials' processes running now (_trial_in_own_process)
_TRIALS_LOCK = threading.Lock()


def _trial_in_own_process(spec):
    """run_trial in a Python process of its own (`--run-spec`): a crash there is that trial's
    error row, not the end of the sweep and its table (the LCM binding has segfaulted in a sweep
    that ran its launchers as threads of one process, 145 trials into 150)."""
    child = subprocess.Popen(_worker_command("--run-spec", json.dumps(spec)),
                             stdout=subprocess.PIPE, text=True)
    with _TRIALS_LOCK:
        _TRIAL_PROCESSES.add(child)
    try:
        out, _ = child.communicate()
    finally:
        with _TRIALS_LOCK:
            _TRIAL_PROCESSES.discard(child)
    lines = out.strip().splitlines()
    if child.returncode == 0 and lines:
        try:
            return json.loads(lines[-1])
        except ValueError:
            pass
    how = (f"killed by signal {-child.returncode}" if child.returncode < 0
           else f"exit {child.returncode}")
    return _error_summary(spec, f"the trial's process died ({how}) in {spec['run_dir']}")


def _worker_command(*args):
    """What a Dask worker runs, for its check and for each trial (and what runs each trial of a
    sweep here, _trial_in_own_process): `python -m dmpl_tools.sweep`
    with this client's Python (the project's venv, at the same path) in the worker's
    environment (its PYTHONPATH), killed with the worker (setpriv: Dask runs a dead worker's
    trial again on another, so the first must not run on). Submitted as subprocess.run with
    plain arguments: the scheduler unpickles every task, and need not have the project's paths."""
    return child_command([sys.executable, "-m", "dmpl_tools.sweep", *args], None)


def worker_facts():
    """What a worker's trials would find (--worker-facts prints it): where its dmpl_tools finds
    the project, what it lacks of it, its Python's version and those of the pinned packages."""
    from .paths import BUILD
    pins = ROOT / "tools" / "requirements.txt"
    names = [line.split("==")[0] for line in pins.read_text().splitlines()
             if "==" in line and not line.startswith("#")] if pins.is_file() else []
    packages = {}
    for name in names:
        try:
            packages[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            packages[name] = None
    return {"root": os.path.realpath(ROOT), "build": os.path.realpath(BUILD),
            "missing": [str(p) for p in (ROOT / "configs", BUILD / "bin" / "dmpl_oneprocess")
                        if not p.exists()],
            "python": platform.python_version(), "packages": packages}


def _worker_problem(check, here):
    """What keeps a worker from running the trials as this client would ("" when nothing), from
    its --worker-facts run: a CompletedProcess, or the exception that kept it from starting."""
    if isinstance(check, Exception):
        return f"cannot run {sys.executable}: {check}"
    if check.returncode != 0:  # dmpl_tools or what it imports is not on the worker's path
        lines = check.stderr.strip().splitlines()
        return lines[-1] if lines else f"the check exited with {check.returncode}"
    there = json.loads(check.stdout.splitlines()[-1])
    problems = [f"lacks {p}" for p in there["missing"]]
    problems += [f"{k} {there[k]} (here {here[k]})" for k in ("root", "build", "python")
                 if there[k] != here[k]]
    problems += [f"{name} {there['packages'].get(name)} (here {here['packages'].get(name)})"
                 for name in sorted(set(here["packages"]) | set(there["packages"]))
                 if there["packages"].get(name) != here["packages"].get(name)]
    return ", ".join(problems)


def _run_on_cluster(address, specs, report):
    """Submits the trials to the Dask scheduler at `address`; its workers need the project at
    the same paths (a shared file system) and its paths on PYTHONPATH: every worker is checked
    first, and the sweep stops with one error naming each that cannot run the trials."""
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise experiment.ExperimentError("--cluster needs dask.distributed (tools/dmpl installs "
                                         "it in the project's venv)") from None
    from .paths import BUILD
    try:
        client = Client(address, timeout=20)
    except (OSError, TimeoutError) as e:
        raise experiment.ExperimentError(f"--cluster {address}: no Dask scheduler there ({e})") \
            from None
    with client:
        if not client.scheduler_info().get("workers"):
            # Workers started just before the sweep may still be connecting.
            print(f"[sweep] waiting up to {WORKER_WAIT_S} s for a worker of {address}",
                  file=sys.stderr, flush=True)
            try:
                client.wait_for_workers(1, timeout=WORKER_WAIT_S)
            except TimeoutError:
                raise experiment.ExperimentError(f"--cluster {address}: the scheduler has no "
                                                 f"workers (waited {WORKER_WAIT_S} s)") from None
        checks = client.run(subprocess.run, _worker_command("--worker-facts"),
                            capture_output=True, text=True, on_error="return")
        here = worker_facts()
        problems = {w: p for w, p in ((w, _worker_problem(c, here)) for w, c in checks.items())
                    if p}
        if problems:
            env = f"PYTHONPATH={BUILD}/python:{ROOT}/tools/python"
            if os.path.realpath(BUILD) != os.path.realpath(ROOT / "build"):
                env += f" DMPL_BUILD_DIR={BUILD}"
            raise experiment.ExperimentError(
                f"--cluster {address}: {len(problems)} of {len(checks)} workers cannot run the "
                "trials:\n" + "".join(f"  {w}: {p}\n" for w, p in sorted(problems.items())) +
                f"Start each worker with the project at {ROOT}, built, and its paths: cd {ROOT} "
                f"&& {env} {Path(sys.executable).parent / 'dask'} worker {address} "
                "(docs/clusters.md)")
        futures = [client.submit(subprocess.run, _worker_command("--run-spec", json.dumps(spec)),
                                 capture_output=True, text=True, pure=False) for spec in specs]
        order = {f.key: i for i, f in enumerate(futures)}
        trials = [None] * len(futures)
        for future in as_completed(futures):
            spec = specs[order[future.key]]
            try:
                done = future.result()
            except Exception as e:  # e.g. KilledWorker: its workers kept dying
                raise experiment.ExperimentError(
                    f"--cluster {address}: the trial of {spec['run_dir']} failed: "
                    f"{type(e).__name__}: {e}") from None
            if done.returncode != 0:
                lines = done.stderr.strip().splitlines()
                raise experiment.ExperimentError(
                    f"--cluster {address}: the trial of {spec['run_dir']} failed on its worker "
                    f"(exit {done.returncode}): {lines[-1] if lines else ''}")
            summary = json.loads(done.stdout.splitlines()[-1])
            trials[order[future.key]] = summary
            report(summary)
        return trials


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl sweep", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common_args(ap, config_optional=True)
    ap.add_argument("--cases", metavar="FILE",
                    help="a base experiment and named cases (configs/benchmarks/*.yaml)")
    ap.add_argument("--seeds", type=int, help="number of trials (per case)")
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2, help="trials at a time (default 2)")
    ap.add_argument("--out", help="output directory (default out/sweeps/NAME-TIME)")
    ap.add_argument("--record", choices=RECORD_POLICIES, default="none",
                    help="what each trial's log keeps (default none: metrics are online)")
    ap.add_argument("--multiprocess", action="store_true",
                    help="full process sets on their own LCM ports instead of one-process mode")
    ap.add_argument("--resume", action="store_true",
                    help="skip the trials already finished in --out (same config and seed)")
    ap.add_argument("--cluster", metavar="ADDRESS",
                    help="run the trials on the workers of this Dask scheduler "
                    "(tcp://HOST:8786; docs/clusters.md)")
    ap.add_argument("--slurm-script", metavar="FILE",
                    help="write an `sbatch --array` script (one trial per task) instead of "
                    "running; gather with --collect OUT")
    ap.add_argument("--collect", metavar="DIR",
                    help="the tables of a --slurm-script sweep from its trials' summaries")
    ap.add_argument("--run-trial", nargs=2, metavar=("TRIALS", "INDEX"),
                    help=argparse.SUPPRESS)  # what a --slurm-script array task runs
    # What a --cluster worker runs: a trial (its summary on stdout), and the check before.
    ap.add_argument("--run-spec", metavar="JSON", help=argparse.SUPPRESS)
    ap.add_argument("--worker-facts", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker_facts:
        print(json.dumps(worker_facts()))
        return 0
    if args.run_spec:
        with contextlib.redirect_stdout(sys.stderr):  # stdout carries the summary only
            summary = run_trial(json.loads(args.run_spec))
        print(json.dumps(summary))
        return 0
    try:
        if args.run_trial:
            summary = run_listed_trial(args.run_trial[0], int(args.run_trial[1]))
            return 0 if summary["status"] == "success" else 1
        if args.collect:
            trials, rate, missing = collect(args.collect)
            print((Path(args.collect) / "sweep.md").read_text())
            if missing:
                print(f"dmpl sweep: {len(missing)} of {len(trials)} trials have no summary yet "
                      f"(first: {missing[0]})", file=sys.stderr)
                return 1
            return 0 if rate == 1.0 else 1
    except (experiment.ExperimentError, ValueError) as e:
        print(f"dmpl sweep: error: {e}", file=sys.stderr)
        return 2
    if args.seeds is None:
        ap.error("--seeds is required")
    if args.seed is not None:
        ap.error("--seed does not apply to a sweep; use --first-seed")
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs must be >= 1")
    if (args.config is None) == (args.cases is None):
        ap.error("give either CONFIG or --cases FILE")
    try:
        cases = load_cases(args.cases) if args.cases else None
    except experiment.ExperimentError as e:
        print(f"dmpl sweep: error: {e}", file=sys.stderr)
        return 2
    title = args.cases or args.config
    name = Path(title).stem
    out = Path(args.out) if args.out else OUT / "sweeps" / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    if args.slurm_script:
        if args.multiprocess or args.cluster:
            ap.error("--slurm-script writes one-process trials; no --multiprocess, --cluster")
        write_slurm_script(args.slurm_script, title, out, trial_specs(
            title, args.seeds, out.resolve(), args.set, args.params, True, args.first_seed,
            record=args.record, cases=cases))
        print(f"sweep: {args.slurm_script} runs {args.seeds} seeds{' per case' if cases else ''} "
              f"as an array job (sbatch {args.slurm_script}); then tools/dmpl sweep --collect {out}")
        return 0
    try:
        trials, rate = run_sweep(title, args.seeds, args.jobs, out, args.set, args.params,
                                 not args.multiprocess, args.first_seed, record=args.record,
                                 cases=cases, resume=args.resume, cluster=args.cluster)
    except (experiment.ExperimentError, SetError) as e:
        print(f"dmpl sweep: error: {e}", file=sys.stderr)
        return 2
    except LcmUnavailable as e:
        print(f"dmpl sweep: error: {e}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:  # the running trials were stopped (run_sweep)
        print("dmpl sweep: interrupted", file=sys.stderr)
        return 130
    print((out / "sweep.md").read_text())
    print(f"sweep: {out / 'sweep.md'}, {out / 'sweep.json'}, {out / 'sweep.parquet'}")
    return 0 if rate == 1.0 else 1


if __name__ == "__main__":
    sys.exit(main())
