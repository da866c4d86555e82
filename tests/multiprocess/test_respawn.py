"""Issue 18: with --respawn, a process of the loop that dies mid-gait is restarted and rejoins it
(lockstep: the others send their last messages again until it answers; real time: it takes up
the latest; the supervisor from its journal), and the summary lists the restart.

In lockstep the run is the run without the kill: it succeeds, every time. In real time what is
sure is that the restarted process takes part in the loop again (its heartbeat's tick runs on
well past the kill) and the run ends with its summary; whether the gait then still succeeds
depends on the machine's load as much as on the restart, and is a rate: `tools/dmpl bench
faults` measures it against runs without a kill (docs/benchmarks.md)."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

import mp
from dmpl import heartbeat_t
from dmpl_tools import channels

GAIT = mp.ROOT + "/configs/experiments/fig10_gait_sphere.yaml"


class RespawnTest(unittest.TestCase):
    def kill_mid_gait(self, victim, *sets, rejoins=True):
        """Runs the gait with --respawn, kills `victim` once the loop is 1.5 s into the run,
        and returns the summary (checked: the restart listed and the restarted process ticking
        with the loop again; in lockstep, a success)."""
        out = Path(tempfile.mkdtemp(prefix="dmpl_respawn_"))
        self.addCleanup(subprocess.run, ["rm", "-rf", str(out)])
        # The run's output goes to a file: the test listens to heartbeats until the run ends.
        log = tempfile.TemporaryFile(mode="w+")
        self.addCleanup(log.close)
        run = subprocess.Popen(
            [sys.executable, "-m", "dmpl_tools.run", GAIT, "--out", str(out), "--respawn",
             "--record", "none", "--set", "task.angle=3.0", *sum((["--set", s] for s in sets), [])],
            cwd=mp.ROOT, stdout=log, stderr=subprocess.STDOUT, text=True)
        bus, state = mp.Bus(), {}

        def on_heartbeat(channel, data):
            hb = heartbeat_t.decode(data)
            if hb.process == victim and hb.state == heartbeat_t.RUNNING:
                state.setdefault("pid", hb.pid)
                if hb.pid != state["pid"]:  # the restarted one: the furthest tick it reached
                    state["rejoined_tick"] = max(state.get("rejoined_tick", -1), hb.seq)
            if hb.process == "dmpl_sim":
                state["tick"] = hb.seq
        bus.subscribe(channels.HEARTBEAT, on_heartbeat)
        bus.wait_for(lambda: "pid" in state and state.get("tick", -1) > 1500, 60,
                     f"{victim} running and the loop 1.5 s in")
        os.kill(state["pid"], signal.SIGKILL)
        killed_at = state["tick"]
        # Heartbeats go on while the run does (every 0.25 s of wall time).
        deadline = time.monotonic() + 180
        while run.poll() is None and time.monotonic() < deadline:
            bus.buses.handle(0.05)
        run.wait(timeout=10)
        log.seek(0)
        output = log.read()
        summary = json.loads((out / "summary.json").read_text())
        if not rejoins:
            return summary, state["tick"]
        self.assertEqual([r["process"] for r in summary["restarts"]], [victim],
                         (summary.get("problems"), output[-3000:]))
        # The launcher knows the tick from heartbeats (every 0.25 s of wall time).
        self.assertGreater(summary["restarts"][0]["sim_time_s"], 0.5)
        # The restarted process took part in the loop: its own tick ran on past the kill (by
        # 0.3 s of the loop; a run that fails afterwards still goes on for stop_after_s).
        self.assertGreater(state.get("rejoined_tick", -1), killed_at + 300, output[-3000:])
        self.assertNotIn("process failure", " ".join(summary.get("problems", [])))
        if "run.lockstep=false" not in sets:
            self.assertEqual(summary["status"], "success", (summary.get("problems"),
                                                            output[-3000:]))
            self.assertGreater(summary["rotation_total_rad"], 2.9)
        return summary

    def test_lockstep_ik_rejoins(self):
        self.kill_mid_gait("dmpl_ik")

    def test_lockstep_noise_rejoins(self):
        self.kill_mid_gait("dmpl_noise")

    def test_lockstep_controller_rejoins(self):
        self.kill_mid_gait("dmpl_controller")

    def test_lockstep_supervisor_takes_up_its_charts(self):
        # It holds the run's charts: the restarted one replays its journal (run.journal_dir)
        # and answers where the old one stopped, as the old one would have: the run is the run
        # without the kill.
        killed = self.kill_mid_gait("dmpl_supervisor")
        out = Path(tempfile.mkdtemp(prefix="dmpl_respawn_clean_"))
        self.addCleanup(subprocess.run, ["rm", "-rf", str(out)])
        subprocess.run([sys.executable, "-m", "dmpl_tools.run", GAIT, "--out", str(out), "--quiet",
                        "--record", "none", "--set", "task.angle=3.0"], cwd=mp.ROOT, check=True,
                       capture_output=True)
        clean = json.loads((out / "summary.json").read_text())
        wall_clock = {"wall_time_s", "realtime_factor", "restarts", "warnings"}
        self.assertEqual(mp.summary_differences(clean, killed, wall_clock), {})

    def test_real_time_supervisor_takes_up_its_charts(self):
        self.kill_mid_gait("dmpl_supervisor", "run.lockstep=false")

    def test_real_time_ik_rejoins(self):
        self.kill_mid_gait("dmpl_ik", "run.lockstep=false")

    def test_real_time_controller_rejoins(self):
        # It starts with no force integrators and takes its contacts from its first reading
        # while the hand holds the last command.
        self.kill_mid_gait("dmpl_controller", "run.lockstep=false")

    def test_real_time_noise_rejoins(self):
        self.kill_mid_gait("dmpl_noise", "run.lockstep=false")


if __name__ == "__main__":
    sys.exit(unittest.main())
