"""tools/dmpl bench faults: how often a process of the loop, killed mid-gait, rejoins it.

Each trial runs the gait (configs/experiments/fig10_gait_sphere.yaml, 3 rad) with --respawn,
kills one process (SIGKILL) at a moment drawn uniformly in 1.2-5.5 s of simulated time
(the simulator's heartbeats tell it), and counts the trial as rejoined when the run still
succeeds with that one restart. Processes are killed in turn (noise, IK, controller, supervisor),
so a machine that gets busier part of the way through weighs on all of them alike. With them,
the same runs without a kill (`none`): a real-time loop on a busy machine can fail without any
fault, and a rejoin rate reads against that baseline.

Keys per process (and `none`): runs, succeeded (rejoined and the run a success), rate, and the
problems of the trials that did not
(their run directories are kept with --keep-failed, recorded with the `analysis` policy).
The simulator is not among them: it is the hand itself, and a hand that restarts drops what
it holds.
"""
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .bus import Buses
from .paths import ROOT

GAIT = ROOT / "configs/experiments/fig10_gait_sphere.yaml"
VICTIMS = ("dmpl_noise", "dmpl_ik", "dmpl_controller", "dmpl_supervisor")
NO_KILL = "none"  # the baseline: the same run, nobody killed


def _heartbeat_type():
    from dmpl import heartbeat_t  # generated at build time (build/python)
    return heartbeat_t


def kill_trial(victim, kill_at_s, lockstep, url, keep_dir=None, tick_s=0.001):
    """One gait run with --respawn whose `victim` is killed at `kill_at_s`; returns a row."""
    from . import channels
    heartbeat_t = _heartbeat_type()
    out = Path(keep_dir) if keep_dir else Path(tempfile.mkdtemp(prefix="dmpl_fault_"))
    record = "analysis" if keep_dir else "none"
    cmd = [sys.executable, "-m", "dmpl_tools.run", str(GAIT), "--out", str(out), "--respawn",
           "--quiet", "--record", record, "--lcm-url", url, "--set", "task.angle=3.0",
           "--set", f"run.lockstep={'true' if lockstep else 'false'}"]
    run = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           text=True)
    buses, state = Buses(url), {}

    def on_heartbeat(channel, data):
        hb = heartbeat_t.decode(data)
        if hb.process == victim and hb.state == heartbeat_t.RUNNING:
            state["pid"] = hb.pid
        if hb.process == "dmpl_sim":
            state["tick"] = hb.seq
    buses.subscribe(channels.HEARTBEAT, on_heartbeat)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and run.poll() is None:
        buses.handle(0.01)
        if victim != NO_KILL and "pid" in state and state.get("tick", -1) * tick_s >= kill_at_s:
            os.kill(state["pid"], signal.SIGKILL)
            state["killed_at_s"] = state["tick"] * tick_s
            break
    output, _ = run.communicate(timeout=300)
    row = {"process": victim, "kill_at_s": state.get("killed_at_s")}
    try:
        summary = json.loads((out / "summary.json").read_text())
    except (OSError, ValueError):
        summary = {"status": "no summary", "problems": [output[-500:]]}
    restarts = [r["process"] for r in summary.get("restarts", [])]
    expected = [] if victim == NO_KILL else [victim]
    row["rejoined"] = (summary.get("status") == "success" and restarts == expected
                       and (victim == NO_KILL or "killed_at_s" in state))
    row["status"] = summary.get("status")
    row["problems"] = summary.get("problems", [])
    row["restarts"] = restarts
    if not keep_dir or row["rejoined"]:
        shutil.rmtree(out, ignore_errors=True)
    else:
        row["run_dir"] = str(out)
    return row


def bench_faults(kills=20, lockstep=False, start_s=1.2, end_s=5.5, seed=1, port=7790,
                 keep_failed=None, victims=VICTIMS + (NO_KILL,), progress=print):
    rng = random.Random(seed)
    url = f"udpm://239.255.76.67:{port}?ttl=0"
    rows = []
    for i in range(kills):
        for victim in victims:
            at = rng.uniform(start_s, end_s)
            keep = Path(keep_failed) / f"{victim}-{i}" if keep_failed else None
            row = kill_trial(victim, at, lockstep, url, keep)
            rows.append(row)
            what = "nobody killed" if victim == NO_KILL else \
                f"{victim} killed at {row['kill_at_s'] or float('nan'):.2f} s"
            progress(f"{what}: "
                     f"{'succeeded' if row['rejoined'] else 'LOST: ' + '; '.join(row['problems'])}")
    result = {"mode": "lockstep" if lockstep else "real time", "seed": seed,
              "kill_window_s": [start_s, end_s]}
    for victim in victims:
        mine = [r for r in rows if r["process"] == victim]
        ok = sum(r["rejoined"] for r in mine)
        result[victim] = {"runs": len(mine), "succeeded": ok, "rate": ok / len(mine),
                          "failures": [r for r in mine if not r["rejoined"]]}
    return result
