"""dmpl's launcher: starts a process set described in YAML, in the manner of libbot2's procman.

A set file:

    name: noise_demo
    lcm_url: udpm://239.255.76.67:7667?ttl=0   # optional; else $LCM_DEFAULT_URL, else the default
    record: true                                # dmpl_record -> RUN_DIR/run.lcmlog
    record_policy: full                         # full | analysis | none (record_policy.h)
    processes:
      - name: noise
        exec: dmpl_noise                        # build/bin first, then PATH
        args: [--config, "${root}/configs/experiments/static_grasp.yaml"]
        env: {DMPL_LOG_LEVEL: info}
        group: sensing
        start_order: 0                          # lower starts first; ties keep file order
        wait_for_heartbeat: true                # the next process starts once this one beats
        auto_respawn: true
        respawn_delay_s: 0.5                    # doubles per restart, up to 8 s
        max_restarts: 3
        stop_signal: SIGINT
        stop_time_allowed: 5.0                  # then SIGKILL
        exit_ends_set: false                    # when this process exits, stop the set
        cpus: [-1]                              # CPU affinity (negative: from the last CPU)

A set-level `cpus` applies to every process that names none; the recorder then runs on the
other CPUs. Pinning a lockstep loop to one CPU makes each hop a local wakeup instead of an
inter-processor one (measured on a 2-core VM: 1.2-2x faster per tick, and steadier); with the
actuation delay (sim.command_delay_ticks >= 1) the simulator on a CPU of its own and the nodes on
another work at once, faster still (run.loop_layout(): 270-290 against 350-390 us per tick).

Each process runs in its own process group (killed as a group: no orphans) with its output
prefixed on the console and kept in RUN_DIR/<name>.log. Process status goes out on
DMPL_PROCESS_STATUS. The launcher exits non-zero when a process failed.
"""
import argparse
import os
import re
import selectors
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from . import channels
from .paths import BUILD, OUT, ROOT, executable

DEFAULT_LCM_URL = channels.DEFAULT_LCM_URL


RECEIVE_BUFFER_BYTES = 4 * 1024 * 1024


def resolve_lcm_url(given=None, configured=None):
    """The LCM URL: the one given (--lcm-url), else the configured one, else $LCM_DEFAULT_URL,
    else the dmpl default (as the nodes resolve it)."""
    return given or configured or os.environ.get("LCM_DEFAULT_URL") or DEFAULT_LCM_URL


def with_receive_buffer(url):
    """Adds a large socket receive buffer to a udpm URL. At 1 kHz lockstep every process reads
    every message on the group (~5 MB/s); the kernel's default 208 KB fills in 40 ms when a
    process is not scheduled, and a lost message stalls the lockstep or leaves a hole in the log.
    The kernel caps it at net.core.rmem_max (tools/dmpl raises that)."""
    if not url.startswith("udpm://") or "recv_buf_size" in url:
        return url
    return url + ("&" if "?" in url else "?") + f"recv_buf_size={RECEIVE_BUFFER_BYTES}"


class SetError(Exception):
    """A bad process set file: reported before anything starts."""


PROCESS_KEYS = {
    "name": str, "exec": str, "args": list, "env": dict, "group": str, "start_order": int,
    "wait_for_heartbeat": bool, "heartbeat_timeout_s": (int, float), "auto_respawn": bool,
    "respawn_delay_s": (int, float), "max_restarts": int, "stop_signal": str,
    "stop_time_allowed": (int, float), "exit_ends_set": bool, "required": bool, "cpus": list,
}
SET_KEYS = {
    "name": str, "lcm_url": str, "record": bool, "record_channels": str, "record_policy": str,
    "processes": list,
    "heartbeat_timeout_s": (int, float), "status_period_s": (int, float), "cpus": list,
}


@dataclass
class ProcessSpec:
    name: str
    exec: str
    args: list = field(default_factory=list)
    env: dict = field(default_factory=dict)
    group: str = ""
    start_order: int = 0
    wait_for_heartbeat: bool = False
    heartbeat_timeout_s: float = 10.0
    auto_respawn: bool = False
    respawn_delay_s: float = 0.5
    max_restarts: int = 3
    stop_signal: str = "SIGINT"
    stop_time_allowed: float = 5.0
    exit_ends_set: bool = False
    required: bool = True
    cpus: list = field(default_factory=list)  # resolved CPU ids; empty: no affinity


RECORD_POLICIES = ("full", "analysis", "none")  # components/logging/record_policy.h


@dataclass
class ProcessSet:
    name: str
    processes: list
    lcm_url: str = ""
    record: bool = True
    record_channels: str = ".*"
    record_policy: str = "full"
    heartbeat_timeout_s: float = 10.0
    status_period_s: float = 0.5
    cpus: list = field(default_factory=list)


def resolve_cpus(cpus, where):
    """CPU ids from a `cpus` list: a non-negative entry is a CPU id, a negative one counts from
    the last CPU this process may use (-1: the last). An unavailable CPU is a SetError."""
    available = sorted(os.sched_getaffinity(0))
    out = []
    for c in cpus:
        if isinstance(c, bool) or not isinstance(c, int):
            raise SetError(f"{where}: key 'cpus' expects CPU numbers, got {c!r}")
        cpu = available[c] if -len(available) <= c < 0 else c
        if cpu not in available:
            raise SetError(f"{where}: key 'cpus': CPU {c} is not available (CPUs here: "
                           f"{', '.join(map(str, available))})")
        if cpu not in out:
            out.append(cpu)
    return out


def _check_keys(where, data, schema):
    if not isinstance(data, dict):
        raise SetError(f"{where}: expected a map, got {type(data).__name__}")
    for key, value in data.items():
        if key not in schema:
            raise SetError(f"{where}: unknown key '{key}'; known keys: {', '.join(sorted(schema))}")
        want = schema[key]
        if isinstance(value, bool) and want in ((int, float), int):
            raise SetError(f"{where}: key '{key}' expects a number, got {value!r}")
        if not isinstance(value, want):
            names = want.__name__ if isinstance(want, type) else " or ".join(t.__name__ for t in want)
            raise SetError(f"{where}: key '{key}' expects {names}, got {value!r}")


def substitute(text, variables):
    """Replaces ${var} with variables[var] or the environment; an unknown variable is an error."""
    def repl(match):
        key = match.group(1)
        if key in variables:
            return str(variables[key])
        if key in os.environ:
            return os.environ[key]
        raise SetError(f"unknown variable ${{{key}}} in '{text}'")
    return re.sub(r"\$\{(\w+)\}", repl, str(text))


def parse_set(data, source, variables):
    """Validates a process set (a dict from YAML) and returns a ProcessSet. Raises SetError."""
    _check_keys(source, data, SET_KEYS)
    if "name" not in data:
        raise SetError(f"{source}: missing key 'name'")
    if not data.get("processes"):
        raise SetError(f"{source}: 'processes' must list at least one process")
    procs, names = [], set()
    for i, p in enumerate(data["processes"]):
        where = f"{source}: processes[{i}]"
        _check_keys(where, p, PROCESS_KEYS)
        for required in ("name", "exec"):
            if required not in p:
                raise SetError(f"{where}: missing key '{required}'")
        if p["name"] in names:
            raise SetError(f"{where}: duplicate process name '{p['name']}'")
        names.add(p["name"])
        spec = ProcessSpec(**p)
        spec.cpus = resolve_cpus(spec.cpus or data.get("cpus", []), where)
        spec.args = [substitute(a, variables) for a in spec.args]
        spec.env = {str(k): substitute(v, variables) for k, v in spec.env.items()}
        try:
            spec.exec = executable(substitute(spec.exec, variables))
        except FileNotFoundError as e:
            raise SetError(f"{where}: {e}") from None
        if not spec.stop_signal.startswith("SIG") or not hasattr(signal, spec.stop_signal):
            raise SetError(f"{where}: unknown stop_signal '{spec.stop_signal}'")
        if spec.stop_time_allowed <= 0 or spec.respawn_delay_s < 0 or spec.max_restarts < 0:
            raise SetError(f"{where}: stop_time_allowed must be > 0, respawn_delay_s and "
                           "max_restarts >= 0")
        procs.append(spec)
    fields = {k: v for k, v in data.items() if k != "processes"}
    if "cpus" in fields:
        fields["cpus"] = resolve_cpus(fields["cpus"], source)
    if "lcm_url" in fields:
        fields["lcm_url"] = substitute(fields["lcm_url"], variables)
    pset = ProcessSet(processes=procs, **fields)
    try:
        re.compile(pset.record_channels)
    except re.error as e:
        raise SetError(f"{source}: record_channels is not a valid regex: {e}") from None
    if pset.record_policy not in RECORD_POLICIES:
        raise SetError(f"{source}: record_policy '{pset.record_policy}': expected one of "
                       f"{', '.join(RECORD_POLICIES)}")
    return pset


def load_set(path, variables):
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise SetError(f"cannot open process set '{path}': {e.strerror}") from None
    except yaml.YAMLError as e:
        raise SetError(f"{path}: YAML syntax error: {e}") from None
    return parse_set(data or {}, str(path), variables)


# Launchers running now (a sweep runs several in threads and stops them all on Ctrl-C).
ACTIVE = set()


class _Proc:
    """One managed process: its spec, its Popen, its state."""

    def __init__(self, spec, run_dir):
        self.spec = spec
        self.popen = None
        self.state = "waiting"
        self.restarts = 0
        self.exit_code = 0
        self.last_heartbeat = 0
        self.heartbeat_seen = False
        self.respawn_at = None
        self.stop_deadline = None
        self.buffer = b""
        self.log = open(run_dir / f"{spec.name}.log", "ab")


class Launcher:
    """Runs a ProcessSet until it ends, a stop is requested, or a duration passes."""

    def __init__(self, pset, run_dir, lcm_url=None, record=None, echo=True, single_bus=False,
                 record_policy=None, columns=None, check_url=True, run_id=None):
        """record: run the recorder (default: the set's `record`); record_policy: what its log
        keeps (default: the set's); columns: (DIR, FIELDS_REGEX) to extract online; check_url:
        refuse a URL another run is heard on (refuse_if_in_use); run_id: the run's identity
        (run.run_id), whose messages alone the recorder records."""
        self.run_id = run_id
        self.pset = pset
        self.run_dir = Path(run_dir)
        self.run_dir.mkdir(parents=True, exist_ok=True)
        self.url = with_receive_buffer(resolve_lcm_url(lcm_url, pset.lcm_url))
        self.record = pset.record if record is None else record
        self.record_policy = record_policy or pset.record_policy
        if self.record_policy not in RECORD_POLICIES:
            raise SetError(f"record policy '{self.record_policy}': expected one of "
                           f"{', '.join(RECORD_POLICIES)}")
        self.columns = columns
        self.echo = echo
        self.single_bus = single_bus
        self.procs = [_Proc(s, self.run_dir) for s in sorted(
            pset.processes, key=lambda s: s.start_order)]  # sorted() is stable: file order on ties
        self.by_name = {p.spec.name: p for p in self.procs}
        self.selector = selectors.DefaultSelector()
        self.all_cpus = sorted(os.sched_getaffinity(0))
        self.stop_requested = None
        self.failed = []
        self.logger = None
        self.ended_by = None
        self.loop_tick = -1   # the newest tick a process of the set reported (heartbeats)
        self.restarts = []    # {"process", "tick"}: the loop's tick when it died
        import lcm  # the PyPI package, in the project's venv
        from dmpl import heartbeat_t
        self._lcm_mod = lcm
        self._heartbeat_t = heartbeat_t
        self.lc = lcm.LCM(self.url)
        if check_url:
            refuse_if_in_use(self.url, self.lc)
        self.lc.subscribe(channels.HEARTBEAT, self._on_heartbeat)
        # LCM is drained every loop (every 50 ms) rather than on each packet: at 1 kHz lockstep
        # every process on the bus gets ~10 000 packets a second, and waking this Python process
        # for each of them would take a core away from the loop it watches.
        self.seq = 0

    # --- output --------------------------------------------------------------------------------
    def say(self, text):
        line = f"[launch] {text}\n"
        sys.stderr.write(line)
        sys.stderr.flush()

    def _pump(self, proc, data, final=False):
        proc.log.write(data)
        proc.log.flush()
        if not self.echo:
            return
        proc.buffer += data
        *lines, proc.buffer = proc.buffer.split(b"\n")
        if final and proc.buffer:
            lines.append(proc.buffer)
            proc.buffer = b""
        for line in lines:
            sys.stdout.write(f"[{proc.spec.name}] {line.decode(errors='replace')}\n")
        sys.stdout.flush()

    # --- LCM -----------------------------------------------------------------------------------
    def _on_heartbeat(self, channel, data):
        try:
            hb = self._heartbeat_t.decode(data)
        except ValueError:
            return
        try:
            group = os.getpgid(hb.pid)
        except (ProcessLookupError, PermissionError, OverflowError):
            return  # not a process of this machine's: not ours
        for p in self.procs:
            # A process is known by its process group (each starts its own: a node under a
            # wrapper script, or every node of dmpl_oneprocess, beats with a pid in it), never by
            # its name, which a process of another run on this URL may share.
            if p.popen and group == p.popen.pid and p.popen.poll() is None:
                p.last_heartbeat = hb.utime
                p.heartbeat_seen = True
                self.loop_tick = max(self.loop_tick, hb.seq)

    def publish_status(self):
        from dmpl import process_info_t, process_status_t
        msg = process_status_t()
        msg.utime = int(time.time() * 1e6)
        msg.seq = self.seq
        self.seq += 1
        msg.set_name = self.pset.name
        msg.run_dir = str(self.run_dir)
        for p in self.procs:
            info = process_info_t()
            info.name = p.spec.name
            info.group = p.spec.group
            info.pid = p.popen.pid if p.popen and p.popen.poll() is None else 0
            info.state = p.state
            info.restarts = p.restarts
            info.exit_code = p.exit_code
            info.last_heartbeat_utime = p.last_heartbeat
            msg.processes.append(info)
        msg.num_processes = len(msg.processes)
        try:
            self.lc.publish(channels.PROCESS_STATUS, msg.encode())
        except OSError:
            pass  # a status lost to the network; the next one follows in status_period_s

    # --- process control -----------------------------------------------------------------------
    def _env(self, spec):
        env = dict(os.environ)
        env["LCM_DEFAULT_URL"] = self.url
        env["PATH"] = f"{BUILD / 'bin'}:{env.get('PATH', '')}"
        env.update(spec.env)
        return env

    def start(self, proc):
        spec = proc.spec
        cmd = [spec.exec] + spec.args
        proc.log.write(f"--- start: {' '.join(cmd)}\n".encode())
        try:
            proc.popen = subprocess.Popen(
                _child_command(cmd, spec.cpus or self.all_cpus), stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=self._env(spec),
                cwd=str(ROOT), start_new_session=True)
        except OSError as e:
            self.say(f"{spec.name}: cannot start: {e}")
            proc.state = "failed"
            proc.exit_code = 127
            self.failed.append(spec.name)
            return
        os.set_blocking(proc.popen.stdout.fileno(), False)
        self.selector.register(proc.popen.stdout, selectors.EVENT_READ, proc)
        proc.state = "starting" if spec.wait_for_heartbeat else "running"
        proc.heartbeat_seen = False
        proc.started_at = time.monotonic()
        self.say(f"started {spec.name} (pid {proc.popen.pid})")

    def _signal_group(self, proc, sig):
        try:
            os.killpg(proc.popen.pid, sig)
        except ProcessLookupError:
            pass

    def stop(self, proc):
        if proc.popen is None or proc.popen.poll() is not None:
            if proc.state in ("waiting", "respawning"):
                proc.state = "stopped"
            return
        proc.state = "stopping"
        proc.stop_deadline = time.monotonic() + proc.spec.stop_time_allowed
        self._signal_group(proc, getattr(signal, proc.spec.stop_signal))

    def _other_cpus(self):
        """The CPUs no process of the set is pinned to (empty when none is pinned or none is
        left over)."""
        loop_cpus = {c for p in self.pset.processes for c in p.cpus}
        if not loop_cpus:
            return []
        return sorted(set(self.all_cpus) - loop_cpus)

    def _start_logger(self):
        if not self.record:
            return
        if self.record_policy == "none" and not self.columns:
            self.say("recording no log (policy none)")
            return
        log_path = self.run_dir / "run.lcmlog"
        args = ["--lcm-url", self.url, "--channels", self.pset.record_channels,
                "--policy", self.record_policy, *(["--single-bus"] if self.single_bus else [])]
        if self.columns:
            args += ["--columns", str(self.columns[0]), "--fields", self.columns[1]]
        if self.run_id:
            args += ["--run-id", str(self.run_id)]
        if self.record_policy != "none":
            args.append(str(log_path))
        # Off the loop's CPUs when the set is pinned: it reads every message of every tick.
        others = self._other_cpus()
        spec = ProcessSpec(name="recorder", exec=executable("dmpl_record"), args=args,
                           required=True, stop_signal="SIGINT", stop_time_allowed=10.0,
                           cpus=others)
        self.logger = _Proc(spec, self.run_dir)
        self.start(self.logger)
        self.logger.state = "running"
        self.say(f"recording LCM traffic to {log_path} (policy {self.record_policy})"
                 if self.record_policy != "none" else "recording no log (policy none)")
        time.sleep(0.2)  # let the logger subscribe before the first message

    # --- the loop ------------------------------------------------------------------------------
    def _read_ready(self, timeout):
        while self.lc.handle_timeout(0) > 0:
            pass
        for key, _ in self.selector.select(timeout):
            proc = key.data
            try:
                data = os.read(key.fileobj.fileno(), 65536)
            except BlockingIOError:
                continue
            if data:
                self._pump(proc, data)
            else:
                self.selector.unregister(key.fileobj)

    def _reap(self, proc, now):
        code = proc.popen.poll()
        if code is None:
            return
        # Drain what is left of its output.
        try:
            self.selector.unregister(proc.popen.stdout)
        except (KeyError, ValueError):
            pass
        try:
            rest = proc.popen.stdout.read() or b""
        except (OSError, ValueError):
            rest = b""
        self._pump(proc, rest, final=True)
        proc.popen.stdout.close()
        proc.exit_code = code
        # Make sure nothing of its group lives on.
        self._signal_group(proc, signal.SIGKILL)
        if proc.state == "stopping":
            proc.state = "stopped"
            return
        how = f"exit code {code}" if code >= 0 else f"signal {signal.Signals(-code).name}"
        spec = proc.spec
        if self.stop_requested is None and spec.exit_ends_set:
            self.say(f"{spec.name} ended ({how}); stopping the set")
            proc.state = "exited" if code == 0 else "failed"
            if code != 0:
                self.failed.append(spec.name)
            self.ended_by = spec.name
            self.request_stop(f"{spec.name} ended")
            return
        if self.stop_requested is None and spec.auto_respawn and proc.restarts < spec.max_restarts:
            delay = min(spec.respawn_delay_s * (2 ** proc.restarts), 8.0)
            proc.restarts += 1
            self.restarts.append({"process": spec.name, "tick": self.loop_tick,
                                  "exit": how})
            proc.state = "respawning"
            proc.respawn_at = now + delay
            self.say(f"{spec.name} died ({how}); respawn {proc.restarts}/{spec.max_restarts} "
                     f"in {delay:.1f} s")
            return
        proc.state = "exited" if code == 0 else "failed"
        if code != 0 or spec.auto_respawn:
            self.say(f"{spec.name} {'failed' if code else 'exited'} ({how})"
                     + (", restart limit reached" if spec.auto_respawn else ""))
            if spec.required:
                # The set cannot do its job without it: end the run now rather than let the
                # others wait for it until a timeout.
                self.failed.append(spec.name)
                self.request_stop(f"{spec.name}, a required process, {'failed' if code else 'exited'}"
                                  f" ({how})")
        else:
            self.say(f"{spec.name} exited ({how})")

    def request_stop(self, why):
        if self.stop_requested is None:
            self.stop_requested = why
            self.say(f"stopping: {why}")
            for p in reversed(self.procs):
                self.stop(p)

    def run(self, duration=None):
        """Starts the set in order and runs until it ends. Returns the exit code. In the main
        thread, SIGINT and SIGTERM stop the set; elsewhere the caller calls request_stop()."""
        previous = {}
        if threading.current_thread() is threading.main_thread():
            previous = {s: signal.signal(s, lambda n, f: self.request_stop(signal.Signals(n).name))
                        for s in (signal.SIGINT, signal.SIGTERM)}
        ACTIVE.add(self)
        # This thread (the launcher) stays off a pinned loop's CPUs while it runs.
        before = os.sched_getaffinity(0)
        others = self._other_cpus()
        if others:
            os.sched_setaffinity(0, others)
        try:
            return self._run(duration)
        finally:
            os.sched_setaffinity(0, before)
            ACTIVE.discard(self)
            for s, h in previous.items():
                signal.signal(s, h)
            for p in self.procs + ([self.logger] if self.logger else []):
                if p.popen and p.popen.poll() is None:
                    self._signal_group(p, signal.SIGKILL)
                    p.popen.wait()
                p.log.close()

    def _run(self, duration):
        self._start_logger()
        t0 = time.monotonic()
        pending = list(self.procs)
        next_status = 0.0
        while True:
            now = time.monotonic()
            # Start the next process once the previous one that must beat has beaten.
            while pending and self.stop_requested is None:
                blocker = next((p for p in self.procs if p.state == "starting"), None)
                if blocker is not None:
                    break
                self.start(pending.pop(0))
            for p in self.procs:
                if p.state == "starting":
                    if p.heartbeat_seen:
                        p.state = "running"
                        self.say(f"{p.spec.name} is up (heartbeat)")
                    elif now - p.started_at > p.spec.heartbeat_timeout_s:
                        self.say(f"{p.spec.name}: no heartbeat within {p.spec.heartbeat_timeout_s} s")
                        self.failed.append(p.spec.name)
                        p.state = "failed"
                        self.request_stop(f"{p.spec.name} did not start")
                if p.popen and p.state in ("starting", "running", "stopping"):
                    self._reap(p, now)
                if p.state == "respawning" and self.stop_requested is None and now >= p.respawn_at:
                    self.start(p)
                if p.state == "stopping" and p.stop_deadline and now > p.stop_deadline:
                    self.say(f"{p.spec.name} did not stop within {p.spec.stop_time_allowed} s: SIGKILL")
                    self._signal_group(p, signal.SIGKILL)
                    p.stop_deadline = None
            if self.logger and self.logger.popen.poll() is not None and self.stop_requested is None:
                self._reap(self.logger, now)
                self.failed.append("recorder")
                self.request_stop("the recorder died: the run would not be recorded")
            if duration is not None and now - t0 > duration:
                self.request_stop(f"duration of {duration} s reached")
            if now >= next_status:
                self.publish_status()
                next_status = now + self.pset.status_period_s
            alive = [p for p in self.procs if p.popen and p.popen.poll() is None]
            if self.stop_requested is not None and not alive and not pending:
                break
            if self.stop_requested is None and not pending and not alive and \
                    all(p.state in ("exited", "failed", "stopped") for p in self.procs):
                self.say("every process has ended")
                break
            self._read_ready(0.05)
        self.publish_status()
        if self.logger and self.logger.popen.poll() is None:
            self.stop(self.logger)
            try:
                self.logger.popen.wait(timeout=self.logger.spec.stop_time_allowed)
            except subprocess.TimeoutExpired:
                self._signal_group(self.logger, signal.SIGKILL)
                self.logger.popen.wait()
            self._reap(self.logger, time.monotonic())
            if self.logger.exit_code != 0:
                self.failed.append("recorder")
        if self.failed:
            self.say(f"failed: {', '.join(sorted(set(self.failed)))}")
            return 1
        return 0


# Every launcher sends its status every 0.5 s (status_period_s): listening this long hears a run
# that is going on.
IN_USE_LISTEN_S = 0.6


def refuse_if_in_use(url, lc=None, listen_s=IN_USE_LISTEN_S):
    """Raises SetError when another run's launcher is heard on `url`: two runs on one URL would
    take each other's messages. Nodes started by hand are not a run (a user or a test may play
    one process of the set). memq:// is private to a process."""
    if not url.startswith("udpm://"):
        return
    if lc is None:
        import lcm
        lc = lcm.LCM(url)
    heard = []

    def on_status(channel, data):
        from dmpl import process_status_t
        try:
            status = process_status_t.decode(data)
            heard.append(f"the launcher of '{status.set_name}' (run directory {status.run_dir})")
        except ValueError:
            heard.append("a launcher")

    sub = lc.subscribe(channels.PROCESS_STATUS, on_status)
    end = time.monotonic() + listen_s
    try:
        while not heard and time.monotonic() < end:
            lc.handle_timeout(max(1, int((end - time.monotonic()) * 1000)))
    finally:
        lc.unsubscribe(sub)
    if heard:
        raise SetError(f"another run is using the LCM URL {url}: heard {heard[0]}. Two runs on "
                       "one URL take each other's messages: stop it, or give this run a URL of "
                       "its own (--lcm-url with another port, e.g. "
                       "udpm://239.255.76.67:7670?ttl=0)")


def _child_command(cmd, cpus):
    """`cmd` so that it dies when the launcher dies, even by SIGKILL (util-linux setpriv:
    PR_SET_PDEATHSIG, kept across exec), and runs on `cpus` (taskset; checked by resolve_cpus;
    not the launcher's own, which may be narrower). Both act in the child before the program
    starts, with no Python between fork and exec: a preexec_fn is unsafe while other threads
    run, and sweeps run launchers from threads."""
    prefix = ["setpriv", "--pdeathsig", "KILL", "--"]
    if cpus:
        prefix += ["taskset", "--cpu-list", ",".join(str(c) for c in sorted(cpus))]
    return prefix + list(cmd)


def _peek_name(path):
    try:
        with open(path) as f:
            data = yaml.safe_load(f) or {}
    except OSError as e:
        raise SetError(f"cannot open process set '{path}': {e.strerror}") from None
    except yaml.YAMLError as e:
        raise SetError(f"{path}: YAML syntax error: {e}") from None
    return str(data.get("name", "set")) if isinstance(data, dict) else "set"


def default_run_dir(name):
    stamp = time.strftime("%Y%m%d-%H%M%S")
    return OUT / "launch" / f"{name}-{stamp}"


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl launch", description="Start a dmpl process set.")
    ap.add_argument("set_file", help="process set YAML (see configs/sets/)")
    ap.add_argument("--run-dir", help="where logs go (default out/launch/NAME-TIME)")
    ap.add_argument("--lcm-url", help="LCM URL for every process (default: the set's, "
                    "$LCM_DEFAULT_URL, or the dmpl default)")
    ap.add_argument("--duration", type=float, help="stop after this many seconds")
    ap.add_argument("--no-record", action="store_true", help="do not run the recorder")
    ap.add_argument("--record", choices=RECORD_POLICIES,
                    help="what the log keeps (default: the set's record_policy, else full)")
    ap.add_argument("--var", action="append", default=[], metavar="KEY=VALUE",
                    help="a ${KEY} for the set file")
    args = ap.parse_args(argv)
    variables = {"root": str(ROOT), "build": str(BUILD)}
    for kv in args.var:
        key, sep, value = kv.partition("=")
        if not sep:
            ap.error(f"--var expects KEY=VALUE, got '{kv}'")
        variables[key] = value
    try:
        name = _peek_name(args.set_file)
        run_dir = Path(args.run_dir) if args.run_dir else default_run_dir(name)
        variables["run_dir"] = str(run_dir)
        pset = load_set(args.set_file, variables)
    except SetError as e:
        print(f"dmpl launch: error: {e}", file=sys.stderr)
        return 2
    try:
        launcher = Launcher(pset, run_dir, lcm_url=args.lcm_url,
                            record=False if args.no_record else None, record_policy=args.record)
    except SetError as e:
        print(f"dmpl launch: error: {e}", file=sys.stderr)
        return 2
    launcher.say(f"set '{pset.name}' with {len(pset.processes)} processes, run dir {run_dir}, "
                 f"LCM {launcher.url}")
    return launcher.run(duration=args.duration)


if __name__ == "__main__":
    sys.exit(main())
