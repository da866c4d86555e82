"""Issue 18: failures end runs promptly and clearly, and two runs cannot share a URL. Each case is
what a user meets: a second run started in another terminal, Ctrl-C, a process that dies, bad
files and values."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from pathlib import Path

import mp
from dmpl import heartbeat_t, sim_status_t
from dmpl_tools import channels
from dmpl_tools.run import run_experiment

EXP = mp.ROOT + "/configs/experiments/"
GAIT = EXP + "fig10_gait_sphere.yaml"


def run_command(*args):
    return [sys.executable, "-m", "dmpl_tools.run", *args]


def wait_for_process(name, timeout=30.0):
    """The pid of the process `name` once its heartbeat says it runs."""
    bus, found = mp.Bus(), {}

    def on_heartbeat(channel, data):
        hb = heartbeat_t.decode(data)
        if hb.process == name and hb.state == heartbeat_t.RUNNING:
            found["pid"] = hb.pid
    bus.subscribe(channels.HEARTBEAT, on_heartbeat)
    bus.wait_for(lambda: "pid" in found, timeout, f"{name} running")
    return found["pid"]


class FaultsTest(unittest.TestCase):
    def setUp(self):
        self.tmp = Path(tempfile.mkdtemp(prefix="dmpl_faults_"))

    def tearDown(self):
        subprocess.run(["rm", "-rf", str(self.tmp)])

    def test_a_second_run_on_the_same_url_is_refused_and_the_first_goes_on(self):
        first = {}
        thread = threading.Thread(target=lambda: first.update(run_experiment(
            GAIT, self.tmp / "first", echo=False, record="none", sets=["task.angle=3.0"])[0]))
        thread.start()
        wait_for_process("dmpl_sim")
        second = subprocess.run(run_command(GAIT, "--out", str(self.tmp / "second"), "--quiet"),
                                cwd=mp.ROOT, capture_output=True, text=True, timeout=120)
        thread.join()
        self.assertEqual(second.returncode, 2, second.stderr)
        self.assertIn("another run is using the LCM URL", second.stderr)
        self.assertNotIn("Traceback", second.stderr)
        self.assertFalse((self.tmp / "second").exists(), "the refused run touched its --out")
        self.assertEqual(first["status"], "success", first.get("problems"))

    def test_an_interrupted_run_says_so(self):
        out = self.tmp / "interrupted"
        run = subprocess.Popen(run_command(GAIT, "--out", str(out), "--quiet"), cwd=mp.ROOT,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        wait_for_process("dmpl_sim")
        time.sleep(1.0)
        run.send_signal(signal.SIGINT)
        output, _ = run.communicate(timeout=60)
        self.assertEqual(run.returncode, 130, output)
        summary = json.loads((out / "summary.json").read_text())
        self.assertEqual(summary["status"], "interrupted")
        self.assertIn("interrupted (SIGINT)", summary["problems"])

    def test_a_required_process_that_dies_ends_the_run_naming_it(self):
        # In real time the others would go on without it until sim.duration_s (200 s).
        out = self.tmp / "died"
        run = subprocess.Popen(run_command(GAIT, "--out", str(out), "--set", "run.lockstep=false",
                                           "--quiet"),
                               cwd=mp.ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True)
        pid = wait_for_process("dmpl_controller")
        # The simulated time when it dies (real time: one simulated second per second).
        bus, sim = mp.Bus(), []
        bus.subscribe(channels.SIM_STATUS, lambda c, d: sim.append(sim_status_t.decode(d)))
        bus.spin(1.0)
        os.kill(pid, signal.SIGKILL)
        bus.spin(0.05)
        killed_at = sim[-1].sim_time_s
        output, _ = run.communicate(timeout=60)
        stopped = [line for line in output.splitlines() if "stopping: dmpl_controller" in line]
        self.assertTrue(stopped, output)
        self.assertEqual(run.returncode, 1, output)
        summary = json.loads((out / "summary.json").read_text())
        self.assertEqual(summary["status"], "failed")
        self.assertIn("process failure: dmpl_controller", summary["problems"])
        # The set stops within a second of the death (the launcher looks every 50 ms).
        self.assertLess(summary["sim_time_s"], killed_at + 1.0)

    def test_bad_files_and_values_are_one_clear_error(self):
        bad_urdf = self.tmp / "bad.urdf"
        text = (Path(mp.ROOT) / "configs/hand/dmpl_hand.urdf").read_text()
        bad_urdf.write_text(text.replace('<child link="F_link0"/>', '<child link="NOPE"/>', 1))
        blocked = self.tmp / "a_file"
        blocked.write_text("")
        cases = [
            ([GAIT, "--out", str(blocked / "run")], "cannot write the run's directory"),
            (["/bin/ls"], "not a YAML text file"),
            ([GAIT, "--params", "/bin/ls"], "not a YAML text file"),
            ([GAIT, "--set", f"hand.urdf={bad_urdf}"], "child link [NOPE] of joint [F_j0] not found"),
            ([GAIT, "--set", "object.mass=-1"], "(given with --set object.mass=-1)"),
            ([GAIT, "--set", "controller.nosuch=1"], "(given with --set controller.nosuch=1)"),
        ]
        for args, message in cases:
            out = [] if "--out" in args else ["--out", str(self.tmp / "out")]
            r = subprocess.run(run_command(*args, *out, "--quiet"), cwd=mp.ROOT,
                               capture_output=True, text=True, timeout=120)
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertIn(message, r.stderr, args)
            self.assertNotIn("Traceback", r.stderr, args)


if __name__ == "__main__":
    sys.exit(unittest.main())
