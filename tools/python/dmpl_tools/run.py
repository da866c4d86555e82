"""tools/dmpl run CONFIG: one experiment -> DIR/summary.json and DIR/run.lcmlog.

--record full|analysis|none (default: the config's run.record, else full) says what the log
keeps (components/logging/record_policy.h); the metrics never depend on it: the recorder extracts
the columns they read from every message while the run goes.
"""
import argparse
import json
import math
import os
import shutil
import sys
import time
import traceback
from pathlib import Path

from . import experiment, metrics
from .launch import Launcher
from .lcm_url import LcmUnavailable, refuse_if_in_use, resolve_lcm_url, with_receive_buffer
from .process_set import RECORD_POLICIES, SetError, parse_set
from .logdata import Columns, LogData, extract, fields_regex
from .paths import BUILD, OUT, ROOT


# The processes --respawn restarts: they rejoin the loop where they left it (the others send
# them their last messages): the noise injector, the IK, the controller (its contacts from its
# first reading, its task from the supervisor), the joint player (a trajectory in time) and the
# supervisor (its charts from its journal, run.journal_dir). The simulator holds the physics:
# its death ends the run.
REJOINING = {"dmpl_noise", "dmpl_ik", "dmpl_controller", "dmpl_joint_player", "dmpl_supervisor"}


def loop_layout():
    """The CPUs a lockstep loop runs fastest on: with two CPUs or more, the simulator on the
    first and every other process on the last, so that physics steps while the nodes compute
    the next command (sim.command_delay_ticks >= 1). Returns (cpus, pins) for run_experiment;
    (None, {}) on one CPU."""
    if len(os.sched_getaffinity(0)) < 2:
        return None, {}
    return [-1], {"dmpl_sim": [0]}


def run_experiment(config_path, out_dir=None, seed=None, sets=(), params=(), lcm_url=None,
                   echo=True, progress=None, one_process=False, record=None, cpus=None,
                   pins=None, respawn=None, only=None):
    """Runs one experiment and returns its summary (also written to OUT/summary.json).

    record: what the log keeps, full | analysis | none (default: the config's run.record);
    False runs no recorder at all, and so computes no metrics (benchmarks of the bare loop).
    one_process: every node in one dmpl_oneprocess on memq:// (lockstep only; same results).
    cpus: pin the experiment's processes to these CPUs (affinity.resolve_cpus; -1 is the last);
    the recorder then runs on the others.
    pins: {process name: CPUs} for single processes, over `cpus` and the config's own.
    respawn: restart a process of the loop that dies (REJOINING), as the config's run.respawn
    says when None.
    only: launch only these processes of the set (the others run elsewhere, e.g. on another
    host: README, "Across two machines")."""
    config = experiment.resolve(config_path, params, sets, seed)
    if respawn is None:
        respawn = bool(config.get("run", {}).get("respawn", False))
    if respawn and one_process:
        raise experiment.ExperimentError("--respawn: one-process mode runs a single process")
    # The run's identity: its processes ignore messages of any other run on the bus, and its
    # recorder records none of them (a positive 62-bit number; 0 would mean none).
    run = config.setdefault("run", {})
    if not run.get("run_id"):
        run["run_id"] = int.from_bytes(os.urandom(8), "big") >> 2
    policy = record_policy(config, record)
    name = config["experiment"]["name"]
    out = Path(out_dir) if out_dir else OUT / "runs" / f"{name}-{time.strftime('%Y%m%d-%H%M%S')}"
    if respawn:
        run["journal_dir"] = str(out.resolve())  # a restarted supervisor takes up from there
    resolved, sensing = out / "config.yaml", out / "config.sensing.yaml"
    url = with_receive_buffer(resolve_lcm_url(lcm_url or config.get("run", {}).get("lcm_url")))
    if not one_process:
        refuse_if_in_use(url)  # before anything in OUT is touched
    try:
        out.mkdir(parents=True, exist_ok=True)
        experiment.write(config, resolved)
        experiment.write(experiment.sensing_view(config), sensing)
    except OSError as e:
        raise experiment.ExperimentError(f"cannot write the run's directory '{out}': "
                                         f"{e.strerror or e}") from None
    experiment.check_processes(resolved, config, sets)
    variables = {"root": str(ROOT), "build": str(BUILD), "run_dir": str(out), "config": str(resolved),
                 "sensing_config": str(sensing)}
    log_path, columns_dir = out / "run.lcmlog", out / "columns"
    for stale in (log_path, out / "summary.json", *out.glob("*.journal")):
        if stale.exists():
            stale.unlink()
    shutil.rmtree(columns_dir, ignore_errors=True)
    columns = (columns_dir, fields_regex(metrics.COLUMNS)) if record is not False else None
    if one_process:
        if not config.get("run", {}).get("lockstep", True):
            raise experiment.ExperimentError("one-process mode runs in lockstep only")
        args = ["--config", str(resolved)]
        if columns:
            args += ["--record-policy", policy, "--columns", str(columns[0]),
                     "--columns-fields", columns[1]]
            if policy != "none":
                args += ["--record", str(log_path)]
        processes = [{"name": "dmpl_oneprocess", "exec": "dmpl_oneprocess", "args": args,
                      "exit_ends_set": True}]
        set_data = {"name": name, "processes": processes, "record": False}
    else:
        processes = _pinned(_only(config["processes"], only), pins or {})
        if respawn:
            # At once: in real time the hand goes on without it meanwhile.
            processes = [dict(p, auto_respawn=True, respawn_delay_s=p.get("respawn_delay_s", 0.05))
                         if p.get("exec") in REJOINING else p for p in processes]
        set_data = {"name": name, "processes": processes}
    if cpus:
        set_data["cpus"] = list(cpus)
    pset = parse_set(set_data, f"{config_path}: processes", variables)
    try:
        launcher = Launcher(pset, out, lcm_url=url, echo=echo,
                            record=columns is not None and not one_process,
                            single_bus=not config.get("run", {}).get("channel_buses", True),
                            record_policy=policy, columns=columns, check_url=False,
                            run_id=run["run_id"])
    except OSError as e:
        raise experiment.ExperimentError(f"cannot write the run's logs in '{out}': "
                                         f"{e.strerror or e}") from None
    if progress:
        progress.attach(launcher)
    launcher.say(f"experiment '{name}' -> {out} (LCM {launcher.url})")
    wall0 = time.monotonic()
    code = launcher.run(duration=config["experiment"].get("timeout_s", 600))
    wall = time.monotonic() - wall0
    if progress:
        progress.done()

    summary = {"status": "failed", "experiment": name, "seed": config.get("run", {}).get("seed", 1),
               "object_shape": config.get("object", {}).get("shape", "sphere"),
               "object_mass_kg": config.get("object", {}).get("mass", 0.05),
               "engine": config.get("sim", {}).get("engine", "bullet"),
               "record_policy": policy if columns else "not recorded"}
    problems = []
    if columns:
        summary.update(_metrics_or_problems(columns_dir, log_path, config, problems))
        shutil.rmtree(columns_dir, ignore_errors=True)
    else:
        summary["note"] = "not recorded: no metrics"
    summary["wall_time_s"] = wall
    sim_time = summary.get("sim_time_s") or 0.0
    summary["realtime_factor"] = sim_time / wall if wall > 0 else 0.0
    summary["exit_code"] = code
    summary["mode"] = "one-process" if one_process else "multi-process"
    if respawn:
        tick_s = _tick_seconds(config)
        summary["restarts"] = [dict(r, sim_time_s=r["tick"] * tick_s if r["tick"] >= 0 else None)
                               for r in launcher.restarts]
    timed_out = launcher.ended_by is None and str(launcher.stop_requested).startswith("duration")
    interrupted = launcher.stop_requested in ("SIGINT", "SIGTERM")
    if timed_out:
        problems.append("wall-clock timeout")
    if interrupted:
        problems.append(f"interrupted ({launcher.stop_requested})")
    if code != 0:
        problems.append(f"process failure: {', '.join(sorted(set(launcher.failed)))}")
    if summary.get("object_dropped") and not config["metrics"]["allow_drop"]:
        problems.append("object dropped")
    if summary.get("supervisor_failed"):
        reason = summary.get("supervisor_reason")
        problems.append("supervisor failed" + (f" ({reason})" if reason else ""))
    if "supervisor_finished" in summary and not summary["supervisor_finished"]:
        problems.append("supervisor did not finish its tasks")
    if (summary.get("log_missing_ticks") or 0) > 0:
        problems.append(f"the log misses {summary['log_missing_ticks']} ticks")
    if "error" in summary:
        problems.append(summary["error"])
    summary = strict_json(summary, problems)  # numpy -> JSON's types; NaN -> null + a problem
    summary["status"] = ("interrupted" if interrupted else "timeout" if timed_out else
                         "failed" if problems else "success")
    if problems:
        summary["problems"] = problems
    try:
        write_summary(out / "summary.json", summary)
    except OSError as e:  # a full or vanished disk: the result still reaches the user
        summary.setdefault("problems", []).append(
            f"{out / 'summary.json'} could not be written: {e.strerror or e}")
        summary["status"] = "failed"
        print(f"dmpl run: error: cannot write {out / 'summary.json'} ({e.strerror or e}); the "
              f"summary:\n{json.dumps(summary, indent=2, sort_keys=True)}", file=sys.stderr)
    return summary, out


def _tick_seconds(config):
    """Simulated seconds per lockstep tick: run.tick_s (the simulator refuses one that is not its
    tick)."""
    return float(config.get("run", {}).get("tick_s", 0.001))


def record_policy(config, record):
    """The run's record policy: `record` if given, else the config's run.record, else full."""
    policy = record if isinstance(record, str) else config.get("run", {}).get("record", "full")
    if policy not in RECORD_POLICIES:
        where = "--record" if isinstance(record, str) else "run.record"
        raise experiment.ExperimentError(f"{where}: unknown record policy '{policy}' (expected "
                                         f"{', '.join(RECORD_POLICIES)})")
    return policy


def _metrics_or_problems(columns_dir, log_path, config, problems):
    """The metrics from the columns the recorder extracted online; from the log when they are
    missing (a recorder that died). Whatever goes wrong becomes a problem, never a traceback
    that loses the summary."""
    try:
        if not (Path(columns_dir) / "meta.json").exists():
            if not Path(log_path).exists():
                return {"error": "the recorder wrote neither columns nor a log: no metrics"}
            problems.append("the recorder wrote no columns: metrics from the log")
            extract(log_path, columns_dir, metrics.COLUMNS)
        data = LogData(Columns(columns_dir))
        out = metrics.compute(data, config)
        if data.problems:  # messages that could not be read: the metrics stand without them
            out["warnings"] = data.problems
        return out
    except Exception as e:  # whatever fails in the metrics must not lose the run's summary
        traceback.print_exc(file=sys.stderr)
        return {"error": f"metrics could not be computed: {type(e).__name__}: {e}"}


def strict_json(value, problems, key="summary"):
    """numpy scalars and containers -> JSON's types; a number that is not finite -> None, with a
    problem naming it (JSON has no NaN)."""
    if isinstance(value, dict):
        return {k: strict_json(v, problems, k) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [strict_json(v, problems, key) for v in value]
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        problems.append(f"{key} is {value}: written as null")
        return None
    return value


def write_summary(path, summary):
    """Writes summary.json atomically (a partial file never replaces a complete one)."""
    tmp = Path(path).with_suffix(".json.tmp")
    try:
        tmp.write_text(json.dumps(summary, indent=2, sort_keys=True, allow_nan=False))
        os.replace(tmp, path)
    except OSError:
        tmp.unlink(missing_ok=True)
        raise


def _only(processes, names):
    """The processes named in `names` (all of them when None); an unknown name is an error."""
    if names is None:
        return processes
    known = [p.get("name") for p in processes]
    for name in names:
        if name not in known:
            raise SetError(f"--only {name}: the experiment has no such process (it has "
                           f"{', '.join(map(str, known))})")
    return [p for p in processes if p.get("name") in names]


def _pinned(processes, pins):
    """The config's processes with `pins` applied; a name the set does not have is an error."""
    names = [p.get("name") for p in processes]
    for name in pins:
        if name not in names:
            raise SetError(f"--pin {name}: the experiment has no such process (it has "
                           f"{', '.join(map(str, names))})")
    return [dict(p, cpus=list(pins[p["name"]])) if p.get("name") in pins else p
            for p in processes]


HEADLINE = ["status", "engine", "object_dropped", "rotation_total_rad",
            "final_orientation_error_rad", "max_position_drift_m", "grip_force_total_n", "contacts_lost", "regrasps",
            "recoveries", "sim_time_s", "wall_time_s", "realtime_factor"]


def print_headline(summary, out, stream=sys.stdout):
    print(f"\nsummary: {out / 'summary.json'}", file=stream)
    for key in HEADLINE:
        if key in summary:
            v = summary[key]
            print(f"  {key:30s} {v:.4g}" if isinstance(v, float) else f"  {key:30s} {v}",
                  file=stream)
    for p in summary.get("problems", []):
        print(f"  problem: {p}", file=stream)
    for w in summary.get("warnings", []):
        print(f"  warning: {w}", file=stream)


def add_common_args(ap, config_optional=False):
    ap.add_argument("config", nargs="?" if config_optional else None,
                    help="experiment config (configs/experiments/*.yaml)")
    ap.add_argument("--seed", type=int, help="run.seed")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override any config key, e.g. object.radius=0.03")
    ap.add_argument("--params", action="append", default=[], metavar="FILE",
                    help="overlay a parameter file (e.g. calibrated gains)")
    ap.add_argument("--lcm-url", help="LCM URL (default: run.lcm_url, $LCM_DEFAULT_URL, or the "
                    "dmpl default)")


def cpu_list(text):
    """--cpus 1 / --cpus -1 / --cpus 0,1 -> [ints]"""
    try:
        return [int(c) for c in text.split(",") if c.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected CPU numbers like 1 or -1 or 0,1, got '{text}'")


def pin_arg(text):
    """--pin dmpl_sim=0 -> ("dmpl_sim", [0])"""
    name, sep, cpus = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=CPUS like dmpl_sim=0, got '{text}'")
    return name, cpu_list(cpus)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl run", description=__doc__)
    add_common_args(ap)
    ap.add_argument("--out", help="output directory (default out/runs/NAME-TIME)")
    ap.add_argument("--quiet", action="store_true", help="keep process output in the log files only")
    ap.add_argument("--record", choices=RECORD_POLICIES,
                    help="what the log keeps (default: the config's run.record, else full)")
    ap.add_argument("--one-process", action="store_true",
                    help="run every node in one process on memq:// (lockstep; same results)")
    ap.add_argument("--cpus", type=cpu_list, metavar="LIST",
                    help="pin the experiment's processes to these CPUs (-1: the last); the "
                    "recorder runs on the others")
    ap.add_argument("--pin", type=pin_arg, action="append", default=[], metavar="NAME=LIST",
                    help="pin one process (e.g. dmpl_sim=0), over --cpus")
    ap.add_argument("--respawn", action="store_true", default=None,
                    help="restart a process of the loop that dies (noise, IK, controller; "
                    "run.respawn); the summary lists the restarts")
    ap.add_argument("--only", type=lambda t: [n for n in t.split(",") if n], metavar="NAMES",
                    help="launch only these processes (comma-separated); the others run "
                    "elsewhere, e.g. on another machine")
    ap.add_argument("--loop-layout", action="store_true",
                    help="the fastest layout of a lockstep loop on two CPUs: --cpus -1 "
                    "--pin dmpl_sim=0 (what demo and bench use)")
    args = ap.parse_args(argv)
    cpus, pins = args.cpus, dict(args.pin)
    if args.loop_layout and not args.one_process:
        layout_cpus, layout_pins = loop_layout()
        cpus, pins = cpus or layout_cpus, {**layout_pins, **pins}
    if args.one_process and (pins or args.only):
        print("dmpl run: error: --pin, --only: one-process mode runs a single process",
              file=sys.stderr)
        return 2
    try:
        summary, out = run_experiment(args.config, args.out, args.seed, args.set, args.params,
                                      args.lcm_url, echo=not args.quiet,
                                      one_process=args.one_process, cpus=cpus, pins=pins,
                                      record=args.record, respawn=args.respawn,
                                      only=args.only)
    except (experiment.ExperimentError, SetError) as e:
        print(f"dmpl run: error: {e}", file=sys.stderr)
        return 2
    except LcmUnavailable as e:
        print(f"dmpl run: error: {e}", file=sys.stderr)
        return 3
    print_headline(summary, out)
    if summary["status"] == "interrupted":
        return 130  # the shell's code for Ctrl-C
    return 0 if summary["status"] == "success" else 1


if __name__ == "__main__":
    sys.exit(main())
