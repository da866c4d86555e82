"""dmpl's launcher: starts a process set (process_set.py) in the manner of libbot2's procman and
supervises it: start order and heartbeats, respawn, a required process that ends the set, stop
with a deadline, the recorder.

Each process runs in its own process group (killed as a group: no orphans) with its output
prefixed on the console and kept in RUN_DIR/<name>.log. Process status goes out on
DMPL_PROCESS_STATUS. The launcher exits non-zero when a process failed.
"""
import argparse
import enum
import os
import selectors
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from . import channels
from .affinity import child_command, this_thread_on, unpinned_cpus
from .lcm_url import (LcmUnavailable, open_lcm, refuse_if_in_use, resolve_lcm_url,
                      with_receive_buffer)
from .paths import BUILD, OUT, ROOT, executable
from .process_set import RECORD_POLICIES, ProcessSpec, SetError, load_set, peek_name


class State(str, enum.Enum):
    """A managed process's state, as DMPL_PROCESS_STATUS carries it."""
    WAITING = "waiting"        # not started yet
    STARTING = "starting"      # started, its heartbeat awaited
    RUNNING = "running"
    RESPAWNING = "respawning"  # died; starts again at respawn_at
    STOPPING = "stopping"      # signalled; SIGKILL at stop_deadline
    STOPPED = "stopped"
    EXITED = "exited"          # ended by itself, exit code 0
    FAILED = "failed"


ENDED = (State.EXITED, State.FAILED, State.STOPPED)


# Launchers running now (a sweep runs several in threads and stops them all on Ctrl-C).
ACTIVE = set()


class _Proc:
    """One managed process: its spec, its Popen, its state."""

    def __init__(self, spec, run_dir):
        self.spec = spec
        self.popen = None
        self.state = State.WAITING
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
        self.lc = open_lcm(self.url)
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
            info.state = p.state.value
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
                child_command(cmd, spec.cpus or self.all_cpus), stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=self._env(spec),
                cwd=str(ROOT), start_new_session=True)
        except OSError as e:
            self.say(f"{spec.name}: cannot start: {e}")
            proc.state = State.FAILED
            proc.exit_code = 127
            self.failed.append(spec.name)
            return
        os.set_blocking(proc.popen.stdout.fileno(), False)
        self.selector.register(proc.popen.stdout, selectors.EVENT_READ, proc)
        proc.state = State.STARTING if spec.wait_for_heartbeat else State.RUNNING
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
            if proc.state in (State.WAITING, State.RESPAWNING):
                proc.state = State.STOPPED
            return
        proc.state = State.STOPPING
        proc.stop_deadline = time.monotonic() + proc.spec.stop_time_allowed
        self._signal_group(proc, getattr(signal, proc.spec.stop_signal))

    def _other_cpus(self):
        """The CPUs no process of the set is pinned to (empty when none is pinned or none is
        left over)."""
        return unpinned_cpus(self.all_cpus, {c for p in self.pset.processes for c in p.cpus})

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
        self.logger.state = State.RUNNING
        self.say(f"recording LCM traffic to {log_path} (policy {self.record_policy})"
                 if self.record_policy != "none" else "recording no log (policy none)")
        time.sleep(0.2)  # let the logger subscribe before the first message

    # --- the loop ------------------------------------------------------------------------------
    def _handle_pending_messages(self):
        while self.lc.handle_timeout(0) > 0:
            pass

    def _read_ready(self, timeout):
        self._handle_pending_messages()
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
        if proc.state == State.STOPPING:
            proc.state = State.STOPPED
            return
        how = f"exit code {code}" if code >= 0 else f"signal {signal.Signals(-code).name}"
        spec = proc.spec
        if self.stop_requested is None and spec.exit_ends_set:
            self.say(f"{spec.name} ended ({how}); stopping the set")
            proc.state = State.EXITED if code == 0 else State.FAILED
            if code != 0:
                self.failed.append(spec.name)
            self.ended_by = spec.name
            self.request_stop(f"{spec.name} ended")
            return
        if self.stop_requested is None and spec.auto_respawn and proc.restarts < spec.max_restarts:
            delay = min(spec.respawn_delay_s * (2 ** proc.restarts), 8.0)
            proc.restarts += 1
            # The tick it died at: heartbeats already received but not yet handled count (the
            # loop can run a second of simulated time between two of them).
            self._handle_pending_messages()
            self.restarts.append({"process": spec.name, "tick": self.loop_tick,
                                  "exit": how})
            proc.state = State.RESPAWNING
            proc.respawn_at = now + delay
            self.say(f"{spec.name} died ({how}); respawn {proc.restarts}/{spec.max_restarts} "
                     f"in {delay:.1f} s")
            return
        proc.state = State.EXITED if code == 0 else State.FAILED
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
        try:
            # This thread (the launcher) stays off a pinned loop's CPUs while it runs.
            with this_thread_on(self._other_cpus()):
                return self._run(duration)
        finally:
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
                blocker = next((p for p in self.procs if p.state == State.STARTING), None)
                if blocker is not None:
                    break
                self.start(pending.pop(0))
            for p in self.procs:
                if p.state == State.STARTING:
                    if p.heartbeat_seen:
                        p.state = State.RUNNING
                        self.say(f"{p.spec.name} is up (heartbeat)")
                    elif now - p.started_at > p.spec.heartbeat_timeout_s:
                        self.say(f"{p.spec.name}: no heartbeat within {p.spec.heartbeat_timeout_s} s")
                        self.failed.append(p.spec.name)
                        p.state = State.FAILED
                        self.request_stop(f"{p.spec.name} did not start")
                if p.popen and p.state in (State.STARTING, State.RUNNING, State.STOPPING):
                    self._reap(p, now)
                if p.state == State.RESPAWNING and self.stop_requested is None and now >= p.respawn_at:
                    self.start(p)
                if p.state == State.STOPPING and p.stop_deadline and now > p.stop_deadline:
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
                    all(p.state in ENDED for p in self.procs):
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
        name = peek_name(args.set_file)
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
    except LcmUnavailable as e:
        print(f"dmpl launch: error: {e}", file=sys.stderr)
        return 3
    launcher.say(f"set '{pset.name}' with {len(pset.processes)} processes, run dir {run_dir}, "
                 f"LCM {launcher.url}")
    return launcher.run(duration=args.duration)


if __name__ == "__main__":
    sys.exit(main())
