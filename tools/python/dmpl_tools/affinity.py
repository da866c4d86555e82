"""CPU affinity for a process set and the commands that start its processes.

Pinning a lockstep loop to one CPU makes each hop a local wakeup instead of an inter-processor
one (measured on a 2-core VM: 1.2-2x faster per tick, and steadier); with the actuation delay
(sim.command_delay_ticks >= 1) the simulator on a CPU of its own and the nodes on another work at
once, faster still (run.loop_layout(): 270-290 against 350-390 us per tick). What is not pinned
(the recorder, the launcher itself) then keeps off the loop's CPUs.
"""
import contextlib
import os


def resolve_cpus(cpus):
    """CPU ids from a `cpus` list: a non-negative entry is a CPU id, a negative one counts from
    the last CPU this process may use (-1: the last). Raises ValueError for one not available."""
    available = sorted(os.sched_getaffinity(0))
    out = []
    for c in cpus:
        if isinstance(c, bool) or not isinstance(c, int):
            raise ValueError(f"expects CPU numbers, got {c!r}")
        cpu = available[c] if -len(available) <= c < 0 else c
        if cpu not in available:
            raise ValueError(f"CPU {c} is not available (CPUs here: "
                             f"{', '.join(map(str, available))})")
        if cpu not in out:
            out.append(cpu)
    return out


def unpinned_cpus(all_cpus, pinned):
    """The CPUs of `all_cpus` outside `pinned` (empty when nothing is pinned or nothing is left)."""
    if not pinned:
        return []
    return sorted(set(all_cpus) - set(pinned))


@contextlib.contextmanager
def this_thread_on(cpus):
    """Runs the calling thread on `cpus` (none: unchanged) for the `with` block."""
    before = os.sched_getaffinity(0)
    if cpus:
        os.sched_setaffinity(0, cpus)
    try:
        yield
    finally:
        os.sched_setaffinity(0, before)


def child_command(cmd, cpus):
    """`cmd` so that it dies when the launcher dies, even by SIGKILL (util-linux setpriv:
    PR_SET_PDEATHSIG, kept across exec), and runs on `cpus` (taskset; checked by resolve_cpus;
    not the launcher's own, which may be narrower). Both act in the child before the program
    starts, with no Python between fork and exec: a preexec_fn is unsafe while other threads
    run, and sweeps run launchers from threads."""
    prefix = ["setpriv", "--pdeathsig", "KILL", "--"]
    if cpus:
        prefix += ["taskset", "--cpu-list", ",".join(str(c) for c in sorted(cpus))]
    return prefix + list(cmd)
