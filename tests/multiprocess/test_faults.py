"""Issue 18: failures end runs promptly and clearly, and two runs cannot share a URL. Each case is
what a user meets: a second run started in another terminal, Ctrl-C, a process that dies, bad
files and values."""
import json
import math
import os
import random
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from pathlib import Path

import mp
from dmpl import (finger_targets_t, hand_sensors_t, heartbeat_t, joint_cmd_t, sim_control_t,
                  sim_status_t)
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


def forge(stop, run_id):
    """Sends bad messages on the loop's channels until `stop` is set: forged ones half with the
    run's identity (they must pass it and be refused by their values), half without (refused for
    that: a run's loop takes no message without its identity)."""
    rng = random.Random(3)
    bus = mp.Bus()
    names = [f"{f}_j{j}" for f in "TFMR" for j in range(4)]

    def sensors(seq, value, n=16):
        m = hand_sensors_t()
        m.seq, m.utime = seq, 0
        m.joints.num_joints, m.joints.name = n, names[:n]
        m.joints.position = m.joints.velocity = m.joints.effort = [value] * n
        return m

    def targets(seq, value, n=16):
        m = finger_targets_t()
        m.seq, m.num_joints, m.joint_position = seq, n, [value] * n
        return m

    def command(seq, value, n=16):
        m = joint_cmd_t()
        m.seq, m.num_joints, m.name, m.position = seq, n, names[:n], [value] * n
        return m

    forged = {channels.SENSORS: sensors, channels.FINGER_TARGETS: targets,
              channels.JOINT_CMD: command}
    every = [channels.SENSORS_TRUE, channels.TASK, channels.CONTROLLER_REPORT,
             channels.HEARTBEAT, channels.SIM_CONTROL, *forged]
    sent = 0
    while not stop.is_set():
        channel = rng.choice(every)
        if channel in forged and rng.random() < 0.5:
            seq = rng.choice([-7, -1, 10 ** 9, 2 ** 62])
            value = rng.choice([math.nan, 1e300, -1e9, 0.3])
            n = rng.choice([16, 3, 0])
            message = forged[channel](seq, value, n)
            message.run_id = rng.choice([0, run_id])
            data = message.encode()
        elif rng.random() < 0.5:
            data = bytes(rng.getrandbits(8) for _ in range(rng.randrange(0, 600)))
        else:
            data = sensors(5, 0.1).encode()
            data = data[:rng.randrange(0, len(data))]
        bus.buses.publish(channel, data)
        sent += 1
        time.sleep(0.003)
    return sent


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

    def test_a_run_goes_on_through_garbage_forgeries_and_a_stray_pause(self):
        # While a lockstep gait runs, this test sends on every channel of the loop random bytes
        # and truncated messages; on the channels only nodes read (the metrics' are the truth,
        # the task and the report), real messages forged with a seq the loop is not at (negative,
        # far ahead) and NaN, huge values or the wrong number of joints, with the run's identity
        # or none; then a PAUSE from nowhere and a RESUME a second later. The run ends as one
        # without any of it.
        clean, _ = run_experiment(GAIT, self.tmp / "clean", echo=False, sets=["task.angle=1.5"])
        result, stop, run_id = {}, threading.Event(), 0x5EED
        thread = threading.Thread(target=lambda: result.update(run_experiment(
            GAIT, self.tmp / "attacked", echo=False,
            sets=["task.angle=1.5", f"run.run_id={run_id}"])[0]))
        thread.start()
        wait_for_process("dmpl_sim")
        forger = threading.Thread(target=forge, args=(stop, run_id))
        forger.start()
        bus = mp.Bus()
        time.sleep(1.0)
        pause = sim_control_t()
        pause.seq, pause.command, pause.reason = -1, sim_control_t.PAUSE, "a stray pause"
        bus.publish(channels.SIM_CONTROL, pause)
        time.sleep(1.0)
        pause.command, pause.reason = sim_control_t.RESUME, "the stray pause's end"
        bus.publish(channels.SIM_CONTROL, pause)
        thread.join()
        stop.set()
        forger.join()
        self.assertEqual(result["status"], "success", result.get("problems"))
        # Under the flood a loop message can be lost in a full socket buffer (2 cores, the
        # forger saturating one): the simulator then waits run.tick_timeout_s, counts a lockstep
        # fault and has the command sent again, and the run goes on as it would have (measured:
        # 1 of 10 runs of this suite, `lockstep_faults` 1, every other key equal). That recovery
        # is what is asserted of it; the rest must not move.
        self.assertLessEqual(result["lockstep_faults"], 2, result.get("last_fault"))
        ignore = {"wall_time_s", "realtime_factor", "warnings", "lockstep_faults", "last_fault"}
        # Equal (mp.summary_differences: the statistics over the per-tick controller statuses
        # to 1e-6).
        self.assertEqual(mp.summary_differences(clean, result, ignore), {})
        sim_log = (self.tmp / "attacked" / "dmpl_sim.log").read_text()
        self.assertIn("by a SIM_CONTROL ('a stray pause')", sim_log)
        self.assertIn("resumed at", sim_log)
        for node in ("dmpl_noise", "dmpl_controller", "dmpl_ik"):
            self.assertIn("is not a", (self.tmp / "attacked" / f"{node}.log").read_text(), node)
        for node in ("dmpl_controller", "dmpl_ik", "dmpl_sim"):  # the forged channels' readers
            self.assertIn("carries no run identity",
                          (self.tmp / "attacked" / f"{node}.log").read_text(), node)

    def test_a_run_ignores_another_runs_messages(self):
        # Another run on the same URL (here forged from this run's own truth, with another
        # run_id) sends the tick each node waits for next, before the real one, a command for the
        # tick the simulator needs, and a PAUSE. Each is ignored and logged; the run gives the
        # summary of a run alone, and its log holds none of them.
        clean, _ = run_experiment(GAIT, self.tmp / "alone", echo=False, sets=["task.angle=1.0"])
        result = {}
        thread = threading.Thread(target=lambda: result.update(run_experiment(
            GAIT, self.tmp / "shared", echo=False, sets=["task.angle=1.0"])[0]))
        thread.start()
        bus, sent = mp.Bus(), {"messages": 0}
        other_run = 12345

        def early(channel, data):
            if sent["messages"] >= 300:
                return
            truth = hand_sensors_t.decode(data)
            truth.run_id = other_run
            for k in (1, 2):
                truth.seq += 1
                bus.buses.publish(channels.SENSORS, truth.encode())
                bus.buses.publish(channels.SENSORS_TRUE, truth.encode())
            cmd = joint_cmd_t()
            cmd.run_id, cmd.seq = other_run, truth.seq - 2
            cmd.num_joints, cmd.name = truth.joints.num_joints, truth.joints.name
            cmd.position = [0.0] * truth.joints.num_joints
            bus.buses.publish(channels.JOINT_CMD, cmd.encode())
            sent["messages"] += 5
        bus.subscribe(channels.SENSORS_TRUE, early)
        pause = sim_control_t()
        pause.run_id, pause.seq, pause.command, pause.reason = other_run, -1, \
            sim_control_t.PAUSE, "another run's pause"
        while thread.is_alive():
            bus.spin(0.05)
            if sent["messages"] >= 100:
                bus.publish(channels.SIM_CONTROL, pause)
        thread.join()
        self.assertGreaterEqual(sent["messages"], 300)
        self.assertEqual(result["status"], "success", result.get("problems"))
        self.assertEqual(
            mp.summary_differences(clean, result, {"wall_time_s", "realtime_factor"}), {})
        for node in ("dmpl_sim", "dmpl_noise", "dmpl_controller"):
            self.assertIn("belongs to another run", (self.tmp / "shared" / f"{node}.log")
                          .read_text(), node)
        self.assertIn("of other runs", (self.tmp / "shared" / "recorder.log").read_text())

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
