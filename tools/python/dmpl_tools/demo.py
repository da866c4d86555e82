"""tools/dmpl demo: the flagship experiment, its log, and a report with the paper's plots.

The paper's sphere is turned a full revolution about x by finger gaiting with 0.5 cm position
noise (configs/experiments/demo.yaml), as the full process set in lockstep. Progress is shown
while it runs; at the end: where the report is, and the headline numbers.
  tools/dmpl demo [--out DIR] [--seed N] [--set key=value]...
"""
import argparse
import sys
import threading
import time

from . import experiment
from .bus import Buses
from .lcm_url import LcmUnavailable
from .process_set import RECORD_POLICIES, SetError
from .logdata import LogError
from .paths import OUT, ROOT
from .report import make_report
from .run import cpu_list, loop_layout, print_headline, run_experiment


class Progress:
    """Prints the supervisor's state and the commanded rotation (or the goals reached and the
    angle to the current one) while the run goes."""

    def __init__(self, stream=sys.stderr, period_s=1.0, name="demo"):
        self.stream, self.period, self.name = stream, period_s, name
        self.last = None
        self.stop = threading.Event()
        self.thread = None

    def attach(self, launcher):
        from dmpl import supervisor_status_t
        self.buses = Buses(launcher.url)
        self.buses.subscribe("DMPL_SUPERVISOR_STATUS",
                             lambda ch, data: setattr(self, "last", supervisor_status_t.decode(data)))
        self.thread = threading.Thread(target=self._loop, daemon=True)
        self.thread.start()

    def _loop(self):
        next_print = time.monotonic() + self.period
        while not self.stop.is_set():
            # Drain now and then instead of waking for each of the bus's ~10 000 packets/s.
            self.stop.wait(0.1)
            self.buses.handle(0)
            if time.monotonic() >= next_print and self.last is not None:
                self.stream.write(f"\r[{self.name}] {self.line(self.last)}  ")
                self.stream.flush()
                next_print += self.period

    @staticmethod
    def line(s):
        """One status line: state, action, and the rotation so far or the goals reached."""
        head = f"sim {s.utime * 1e-6:6.2f} s  {s.grasp_state:<11} {s.regrasp_state} " \
               f"{s.last_action:<16.16} "
        if s.num_goals:
            return head + (f"goals {s.goals_reached}/{s.num_goals}  error "
                           f"{s.goal_error_rad:.2f} rad  regrasps {s.regrasps}")
        goal = f" of {s.rotation_goal_rad:.2f}" if s.rotation_goal_rad else ""
        return head + (f"rotation {s.rotation_commanded_rad:+.2f}{goal} rad  "
                       f"regrasps {s.regrasps}")

    def done(self):
        """Ends the progress with the last status heard (a short run may end before the first
        period)."""
        self.stop.set()
        if self.thread:
            self.thread.join(timeout=1)
            self.buses.handle(0)
        if self.last is not None:
            self.stream.write(f"\r[{self.name}] {self.line(self.last)}  ")
        self.stream.write("\n")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl demo", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(OUT / "demo"))
    ap.add_argument("--seed", type=int)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--config", default=str(ROOT / "configs/experiments/demo.yaml"))
    ap.add_argument("--record", choices=RECORD_POLICIES,
                    help="what the log keeps (default: the demo's, analysis)")
    ap.add_argument("--cpus", type=cpu_list, metavar="LIST",
                    help="the CPUs of the loop; '' lets the scheduler place it (default: with "
                    "two CPUs or more the simulator on the first, the nodes on the last)")
    args = ap.parse_args(argv)
    cpus, pins = loop_layout() if args.cpus is None else (args.cpus or None, {})
    print(f"[demo] {args.config}: the sphere turned by finger gaiting; out: {args.out}",
          file=sys.stderr)
    try:
        summary, out = run_experiment(args.config, args.out, seed=args.seed, sets=args.set,
                                      echo=False, progress=Progress(), cpus=cpus, pins=pins,
                                      record=args.record)
    except (experiment.ExperimentError, SetError) as e:
        print(f"dmpl demo: error: {e}", file=sys.stderr)
        return 2
    except LcmUnavailable as e:
        print(f"dmpl demo: error: {e}", file=sys.stderr)
        return 3
    log = out / "run.lcmlog"
    print_headline(summary, out)
    if log.exists():
        try:
            report = make_report(log, out / "report", replay_path=out / "replay.html")
            print(f"\nreport: {report}")
            if (out / "replay.html").exists():
                print(f"replay: {out / 'replay.html'} (3-D, opens offline in a browser)")
        except (LogError, OSError) as e:  # the summary is written; say why there is no report
            print(f"\nreport: not written: {e}")
        print(f"log:    {log} ({summary.get('record_policy')}; tools/dmpl replay it for "
              "tools/dmpl spy)")
    if summary["status"] == "interrupted":
        return 130  # as tools/dmpl run: the shell's code for Ctrl-C
    return 0 if summary["status"] == "success" else 1


if __name__ == "__main__":
    sys.exit(main())
