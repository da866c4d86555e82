"""tools/dmpl sweep CONFIG --seeds N [--jobs J] [--out DIR] [--set key=value]... [--multiprocess]

N trials of one experiment with seeds 1..N (or --first-seed S..), J at a time. Each trial runs in
one-process mode (no sockets shared, nothing to collide); --multiprocess runs the full process
set instead, each trial on its own LCM port. Writes DIR/sweep.md (a table), DIR/sweep.json
(keys `trials`, `success_rate`, and one summary per trial), DIR/sweep.parquet (one row per trial,
for pandas and polars) and each trial's run directory. Trials keep no log by default (--record
none: their metrics are computed online); --record analysis or full keeps one per trial.
"""
import argparse
import json
import os
import queue
import statistics
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from . import experiment
from .launch import ACTIVE, RECORD_POLICIES, SetError
from .paths import ROOT
from .run import add_common_args, run_experiment, strict_json

COLUMNS = [("seed", "seed", "{}"), ("status", "status", "{}"),
           ("rotation_total_rad", "rotation (rad)", "{:.3f}"),
           ("final_orientation_error_rad", "final error (rad)", "{:.4f}"),
           ("max_position_drift_m", "drift (m)", "{:.4f}"),
           ("grip_force_total_n", "grip (N)", "{:.2f}"), ("contacts_lost", "contacts lost", "{}"),
           ("regrasps", "regrasps", "{}"), ("object_dropped", "dropped", "{}"),
           ("sim_time_s", "sim time (s)", "{:.1f}"), ("realtime_factor", "RTF", "{:.2f}")]


def _cell(summary, key, fmt):
    v = summary.get(key)
    if v is None:
        return "-"
    try:
        return fmt.format(v)
    except (ValueError, TypeError):
        return str(v)


def write_table(out, config_path, trials):
    rows = ["| " + " | ".join(c[1] for c in COLUMNS) + " |",
            "| " + " | ".join("---" for _ in COLUMNS) + " |"]
    for s in trials:
        rows.append("| " + " | ".join(_cell(s, k, f) for k, _, f in COLUMNS) + " |")
    ok = [s for s in trials if s.get("status") == "success"]
    rate = len(ok) / len(trials) if trials else 0.0
    lines = [f"# Sweep of `{config_path}`", "",
             f"{len(ok)} of {len(trials)} trials succeeded (success rate {rate:.0%}).", ""]
    for key, label in (("rotation_total_rad", "rotation"), ("final_orientation_error_rad",
                                                          "final orientation error"),
                       ("realtime_factor", "real-time factor")):
        vals = [s[key] for s in trials if isinstance(s.get(key), (int, float))]
        if vals:
            lines.append(f"- {label}: median {statistics.median(vals):.4g}, "
                         f"min {min(vals):.4g}, max {max(vals):.4g}")
    lines += ["", *rows, ""]
    (out / "sweep.md").write_text("\n".join(lines))
    doc = {"config": str(config_path), "trials": len(trials), "succeeded": len(ok),
           "success_rate": rate, "summaries": trials}
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


def run_sweep(config_path, seeds, jobs, out, sets=(), params=(), one_process=True,
              first_seed=1, port_base=7900, record="none"):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    lock = threading.Lock()
    done = []
    # With no more trials at a time than CPUs, each trial runs on a CPU of its own (a pinned
    # loop wakes its processes locally; see launch.py); otherwise the scheduler places them.
    available = sorted(os.sched_getaffinity(0))
    pinned = jobs <= len(available)
    cpus = queue.Queue()
    for c in available:
        cpus.put(c)

    def trial(i):
        seed = first_seed + i
        url = None if one_process else f"udpm://239.255.76.67:{port_base + i}?ttl=0"
        cpu = cpus.get() if pinned else None
        try:
            summary, _ = run_experiment(config_path, out / f"seed{seed}", seed=seed, sets=sets,
                                        params=params, lcm_url=url, echo=False,
                                        one_process=one_process, record=record,
                                        cpus=None if cpu is None else [cpu])
        finally:
            if cpu is not None:
                cpus.put(cpu)
        with lock:
            done.append(seed)
            rotation = summary.get("rotation_total_rad")
            print(f"[sweep] seed {seed}: {summary['status']}, rotation "
                  f"{'-' if rotation is None else f'{rotation:.3f}'} rad, "
                  f"{len(done)}/{seeds} done", file=sys.stderr, flush=True)
        return summary

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(trial, i) for i in range(seeds)]
        try:
            trials = [f.result() for f in futures]
        except KeyboardInterrupt:
            for f in futures:
                f.cancel()
            for launcher in list(ACTIVE):
                launcher.request_stop("sweep interrupted")
            raise
    rate = write_table(out, config_path, trials)
    return trials, rate


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl sweep", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common_args(ap)
    ap.add_argument("--seeds", type=int, required=True, help="number of trials")
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2, help="trials at a time (default 2)")
    ap.add_argument("--out", help="output directory (default out/sweeps/NAME-TIME)")
    ap.add_argument("--record", choices=RECORD_POLICIES, default="none",
                    help="what each trial's log keeps (default none: metrics are online)")
    ap.add_argument("--multiprocess", action="store_true",
                    help="full process sets on their own LCM ports instead of one-process mode")
    args = ap.parse_args(argv)
    if args.seed is not None:
        ap.error("--seed does not apply to a sweep; use --first-seed")
    if args.seeds < 1 or args.jobs < 1:
        ap.error("--seeds and --jobs must be >= 1")
    name = Path(args.config).stem
    out = Path(args.out) if args.out else ROOT / "out" / "sweeps" / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    try:
        trials, rate = run_sweep(args.config, args.seeds, args.jobs, out, args.set, args.params,
                                 not args.multiprocess, args.first_seed, record=args.record)
    except (experiment.ExperimentError, SetError) as e:
        print(f"dmpl sweep: error: {e}", file=sys.stderr)
        return 2
    print((out / "sweep.md").read_text())
    print(f"sweep: {out / 'sweep.md'}, {out / 'sweep.json'}, {out / 'sweep.parquet'}")
    return 0 if rate == 1.0 else 1


if __name__ == "__main__":
    sys.exit(main())
