"""tools/dmpl bench loop: the closed loop at 1 kHz in lockstep, multi-process against one-process,
measured side by side in one run, and the raw LCM hop measured by the benchmark itself.

The loop as it runs by default: a one-tick actuation delay (sim.command_delay_ticks = 1) and,
on two CPUs, the simulator on the first and the nodes on the last (run.loop_layout()), so that
physics steps while the nodes compute the next command. Beside it, the loop without the delay
(every process on the last CPU: without a delay nothing can run in parallel, and a local
wakeup is the cheapest) and the loop with the scheduler free.

Keys: rtf_multiprocess, rtf_oneprocess (steady state, from the simulator's own clock, recording
off; the median of five alternating rounds), rtf_oneprocess_mujoco and tick_us_oneprocess_mujoco
(the one-process loop with sim.engine=mujoco, in the same rounds; the one-process loop runs on
the CPUs the multi-process one gets, its physics on a thread of its own: sim.background_step),
rtf_oneprocess_mujoco_one_cpu and tick_us_oneprocess_mujoco_one_cpu (the same pinned to one
CPU, where the physics steps on the nodes' thread), rtf_multiprocess_no_delay,
rtf_multiprocess_unpinned, tick_us_multiprocess, tick_us_oneprocess, tick_overhead_us (what
multi-process adds per tick; with the delay part of it runs in parallel), lcm_hop_us (half a
ping-pong round trip of a message of the loop's mean size between two processes on one CPU;
lcm_hop_us_unpinned with the scheduler free), hops_per_tick (sim -> noise -> controller -> IK
-> sim), overhead_vs_raw = tick_overhead_us / (hops_per_tick * lcm_hop_us) and the same without
the delay (overhead_vs_raw_no_delay: what the framework adds over bare LCM when nothing
overlaps); in real time, latency_p50_us and latency_p99_us from a sensor tick to the command
that answers it; the CPU time per tick of each process; and steal_multiprocess, steal_max: the
CPU time a virtual machine's host took per second of the chosen and of the worst run (a host
that takes a CPU stalls a loop spread over two: read the rtf with it).
"""
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import lcm

from .paths import ROOT, executable
from .affinity import resolve_cpus
from .run import loop_layout, run_experiment

SCENARIO = ROOT / "configs/experiments/fig8_sphere.yaml"
HOP_CHANNELS = ["DMPL_SENSORS_TRUE", "DMPL_SENSORS", "DMPL_FINGER_TARGETS", "DMPL_JOINT_CMD"]
HOPS_PER_TICK = 4


ONE_CPU = [-1]
DELAY = 1  # sim.command_delay_ticks of the loop as it runs by default


def _stolen_cpu_s():
    """CPU time the hypervisor took from this machine's CPUs so far (/proc/stat 'steal')."""
    with open("/proc/stat") as f:
        fields = f.readline().split()
    return int(fields[8]) / os.sysconf("SC_CLK_TCK") if len(fields) > 8 else 0.0


def _run(tmp, tag, one_process, sets=(), cpus=ONE_CPU, pins=None):
    """One run's simulator stats, with `steal`: the CPUs' time the hypervisor took per second
    of the run (0.25: a quarter of a CPU; a loop on two CPUs then waits for the one taken)."""
    stats = Path(tmp) / f"{tag}.json"
    stolen = _stolen_cpu_s()
    run_experiment(SCENARIO, Path(tmp) / tag, sets=[f"sim.stats_file={stats}", *sets],
                   echo=False, one_process=one_process, record=False, cpus=cpus, pins=pins)
    result = json.loads(stats.read_text())
    result["steal"] = (_stolen_cpu_s() - stolen) / max(result["wall_time_s"], 1e-9)
    return result, Path(tmp) / tag


def _mean_message_bytes(tmp):
    out = Path(tmp) / "sizes"
    run_experiment(SCENARIO, out, sets=["sim.duration_s=0.3"], echo=False, one_process=True)
    log = lcm.EventLog(str(out / "run.lcmlog"), "r")
    sizes = [len(e.data) for e in log if e.channel in HOP_CHANNELS]
    log.close()
    return int(statistics.mean(sizes)) if sizes else 600


def _hop_us(nbytes, cpus=None):
    """Half the median ping-pong round trip; both ends on `cpus` when given (as the loop runs)."""
    pin = ["taskset", "--cpu-list", ",".join(str(c) for c in cpus)] if cpus else []
    echo = subprocess.Popen(pin + [executable("dmpl_bench_lcm_hop"), "echo"])
    try:
        time.sleep(0.3)
        out = subprocess.run(pin + [executable("dmpl_bench_lcm_hop"), "ping", "--bytes", str(nbytes)],
                             capture_output=True, text=True, check=True, timeout=120)
        return json.loads(out.stdout)
    finally:
        echo.terminate()
        echo.wait()


def _cpu_per_tick(run_dir, ticks):
    """CPU time per tick of each process, from the 'cpu time' line every node logs at exit."""
    out = {}
    for log in Path(run_dir).glob("dmpl_*.log"):
        m = re.findall(r"cpu time user ([0-9.]+) s, system ([0-9.]+) s", log.read_text())
        if m:
            user, system = map(float, m[-1])
            out[log.stem] = round((user + system) * 1e6 / max(ticks, 1), 1)
    return out


def _median(runs):
    """The run of median tick time: (stats, run dir)."""
    return sorted(runs, key=lambda x: x[0]["tick_us"])[len(runs) // 2]


def bench_loop(rounds=5):
    """Alternates the runs `rounds` times and takes the medians: a virtual machine's timing
    wanders from one second to the next."""
    delayed, no_delay = [f"sim.command_delay_ticks={DELAY}"], ["sim.command_delay_ticks=0"]
    layout_cpus, layout_pins = loop_layout()
    with tempfile.TemporaryDirectory(prefix="dmpl_bench_loop_") as tmp:
        nbytes = _mean_message_bytes(tmp)
        hop = _hop_us(nbytes, resolve_cpus(ONE_CPU))
        hop_free = _hop_us(nbytes)
        # One process on the CPUs the multi-process loop gets (its physics steps on a thread of
        # its own: sim.background_step), and on one CPU as well.
        one_cpus = [0, -1] if layout_cpus else ONE_CPU
        runs = {"multi": [], "one": [], "one_mujoco": [], "one_mujoco_one_cpu": [],
                "no_delay": [], "free": []}
        for r in range(rounds):
            runs["multi"].append(_run(tmp, f"multi{r}", False, delayed, layout_cpus, layout_pins))
            runs["one"].append(_run(tmp, f"one{r}", True, delayed, one_cpus))
            runs["one_mujoco"].append(_run(tmp, f"onemj{r}", True, [*delayed, "sim.engine=mujoco"],
                                           one_cpus))
            runs["one_mujoco_one_cpu"].append(
                _run(tmp, f"onemj1{r}", True, [*delayed, "sim.engine=mujoco"]))
            runs["no_delay"].append(_run(tmp, f"nodelay{r}", False, no_delay))
            runs["free"].append(_run(tmp, f"free{r}", False, delayed, cpus=None))
            print(f"round {r + 1}/{rounds}: us/tick (stolen CPU per s) "
                  + ", ".join(f"{label} {runs[key][-1][0]['tick_us']:.0f} "
                              f"({runs[key][-1][0]['steal']:.2f})"
                              for key, label in (("multi", "multi-process"),
                                                 ("one", "one-process"),
                                                 ("one_mujoco", "one-process MuJoCo"),
                                                 ("one_mujoco_one_cpu",
                                                  "one-process MuJoCo on one CPU"),
                                                 ("no_delay", "multi-process without the delay"),
                                                 ("free", "multi-process unpinned"))),
                  file=sys.stderr)
        (multi, multi_dir), (one, _) = _median(runs["multi"]), _median(runs["one"])
        one_mujoco, _ = _median(runs["one_mujoco"])
        one_mujoco_one_cpu, _ = _median(runs["one_mujoco_one_cpu"])
        (bare, bare_dir), (free, _) = _median(runs["no_delay"]), _median(runs["free"])
        # Real time as a real hand runs it: the scheduler free.
        realtime, _ = _run(tmp, "realtime", False, [*delayed, "run.lockstep=false"], cpus=None)
        raw = HOPS_PER_TICK * hop["lcm_hop_us"]
        overhead = multi["tick_us"] - one["tick_us"]
        overhead_bare = bare["tick_us"] - one["tick_us"]
        result = {
            "rtf_multiprocess": multi["realtime_factor"],
            "rtf_oneprocess": one["realtime_factor"],
            "rtf_oneprocess_mujoco": one_mujoco["realtime_factor"],
            "rtf_oneprocess_mujoco_one_cpu": one_mujoco_one_cpu["realtime_factor"],
            "rtf_multiprocess_no_delay": bare["realtime_factor"],
            "rtf_multiprocess_unpinned": free["realtime_factor"],
            "command_delay_ticks": DELAY,
            "loop_cpus": {"dmpl_sim": layout_pins.get("dmpl_sim", layout_cpus),
                          "others": layout_cpus, "no_delay": ONE_CPU, "one_process": one_cpus},
            "tick_us_multiprocess": multi["tick_us"],
            "tick_us_oneprocess": one["tick_us"],
            "tick_us_oneprocess_mujoco": one_mujoco["tick_us"],
            "tick_us_oneprocess_mujoco_one_cpu": one_mujoco_one_cpu["tick_us"],
            "tick_us_multiprocess_no_delay": bare["tick_us"],
            "tick_overhead_us": overhead,
            "tick_overhead_us_no_delay": overhead_bare,
            "lcm_hop_us": hop["lcm_hop_us"],
            "lcm_hop_us_unpinned": hop_free["lcm_hop_us"],
            "lcm_hop_bytes": nbytes,
            "hops_per_tick": HOPS_PER_TICK,
            "overhead_vs_raw": overhead / raw,
            "overhead_vs_raw_no_delay": overhead_bare / raw,
            "latency_p50_us": realtime["latency_p50_us"],
            "latency_p99_us": realtime["latency_p99_us"],
            "realtime_late_commands": realtime["late_commands"],
            "steal_multiprocess": multi["steal"],
            "steal_max": max(x[0]["steal"] for v in runs.values() for x in v),
            "cpu_us_per_tick_multiprocess": _cpu_per_tick(multi_dir, multi["ticks"]),
            "cpu_us_per_tick_multiprocess_no_delay": _cpu_per_tick(bare_dir, bare["ticks"]),
            "ticks": multi["ticks"],
            "rounds": rounds,
        }
    return result


if __name__ == "__main__":
    print(json.dumps(bench_loop(), indent=2))
    sys.exit(0)
