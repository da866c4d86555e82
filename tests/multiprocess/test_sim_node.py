"""dmpl_sim's lockstep protocol, driven by this test as the only participant: commands with the
right seq advance the simulation; NaN and out-of-limit commands are rejected, counted and never
reach the physics; a missing command is a fault reported with its seq, and too many end the run;
with an actuation delay of d ticks the simulator runs d ticks ahead and a command acts exactly d
ticks later. Bad URDF and config files stop the process before it runs, naming the file and the
problem."""
import math
import os
import subprocess
import sys
import tempfile
import time
import unittest

import mp
from dmpl import hand_sensors_t, heartbeat_t, joint_cmd_t, sim_control_t, sim_status_t

CONFIG = """
run: {lockstep: true, lockstep_participants: [test_driver], tick_timeout_s: 0.3, max_tick_faults: 2,
      resend_after_s: RESEND}
sim: {duration_s: 5.0, command_delay_ticks: DELAY}
object: {position: [0.3, 0.5, 0.5], held: false}
"""


def write(text, suffix=".yaml"):
    fd, path = tempfile.mkstemp(suffix=suffix)
    with os.fdopen(fd, "w") as f:
        f.write(text)
    return path


class SimNodeTest(unittest.TestCase):
    def start(self, delay, resend_after_s=0.0):
        """Starts dmpl_sim with this test as its only participant; returns (process, bus,
        states, answer), answer(k, q) sending the command for tick k and waiting for the tick
        it makes the simulator publish."""
        bus = mp.Bus()
        # The joints of every tick's truth.
        bus.subscribe("DMPL_SENSORS_TRUE", lambda ch, data: bus.received.setdefault(ch, []).append(
            hand_sensors_t.decode(data).joints))
        bus.listen("DMPL_SIM_STATUS", sim_status_t)
        sim = subprocess.Popen([os.path.join(os.environ["DMPL_BUILD_DIR"], "bin", "dmpl_sim"),
                                "--config", write(CONFIG.replace("DELAY", str(delay))
                                                 .replace("RESEND", str(resend_after_s)))],
                               cwd=mp.ROOT)
        self.addCleanup(lambda: sim.poll() is None and sim.kill())
        hb = heartbeat_t()
        hb.process, hb.pid, hb.state = "test_driver", os.getpid(), heartbeat_t.RUNNING
        bus.wait_for(lambda: (bus.publish("DMPL_HEARTBEAT", hb) or True) and
                     len(bus.received.get("DMPL_SENSORS_TRUE", [])) > delay, 10,
                     f"ticks 0..{delay}")
        states = bus.received["DMPL_SENSORS_TRUE"]
        names = list(states[0].name)

        def answer(k, q):
            cmd = joint_cmd_t()
            cmd.seq, cmd.num_joints, cmd.name, cmd.position = k, len(names), names, q
            bus.publish("DMPL_JOINT_CMD", cmd)
            bus.wait_for(lambda: len(states) > k + delay + 1, 5, f"tick {k + delay + 1}")
            self.assertEqual(states[k + delay + 1].seq, k + delay + 1)

        return sim, bus, states, answer

    def test_a_command_acts_exactly_the_delay_later(self):
        delay = 2
        sim, bus, states, answer = self.start(delay)
        bus.spin(0.2)
        self.assertEqual(len(states), delay + 1, "stepped past the delay without a command")
        names = list(states[0].name)
        q0 = list(states[0].position)
        m1 = names.index("M_j1")
        bent = list(q0)
        bent[m1] = q0[m1] + 0.3
        for k in range(10):
            answer(k, q0)
        for k in range(10, 20):
            answer(k, bent)
        # The command of tick 10 drives the step from tick 12: tick 13 is the first that moves.
        at_rest = max(abs(s.velocity[m1]) for s in states[:13])
        self.assertLess(at_rest, 0.02)
        self.assertGreater(states[13].velocity[m1], 10 * max(at_rest, 0.01))
        # Stop answering: the fault names the command the next step needs.
        self.assertEqual(sim.wait(timeout=10), 4)
        bus.spin(0.1)
        faults = [s for s in bus.received["DMPL_SIM_STATUS"] if s.faults > 0]
        self.assertTrue(faults)
        self.assertIn("no JOINT_CMD for seq 20", faults[-1].last_fault)

    def test_over_a_lossy_network_it_sends_an_unanswered_tick_again(self):
        # run.resend_after_s: while no command comes, the truth of the ticks waiting for one is
        # sent again, the same bytes; tick 1 waits for the answer to tick 0 (so that every node
        # starts at tick 0, whatever is lost), then the delay holds as without loss.
        delay = 2
        bus = mp.Bus()
        raw = []
        bus.subscribe("DMPL_SENSORS_TRUE", lambda ch, data: raw.append(data))
        sim = subprocess.Popen([os.path.join(os.environ["DMPL_BUILD_DIR"], "bin", "dmpl_sim"),
                                "--config", write(CONFIG.replace("DELAY", str(delay))
                                                  .replace("RESEND", "0.01"))], cwd=mp.ROOT)
        self.addCleanup(lambda: sim.poll() is None and sim.kill())
        hb = heartbeat_t()
        hb.process, hb.pid, hb.state = "test_driver", os.getpid(), heartbeat_t.RUNNING
        bus.wait_for(lambda: (bus.publish("DMPL_HEARTBEAT", hb) or True) and len(raw) >= 3, 10,
                     "tick 0 and two copies of it")
        self.assertEqual({hand_sensors_t.decode(d).seq for d in raw}, {0})
        self.assertEqual(len(set(raw)), 1, "a copy differs from the original")
        names = list(hand_sensors_t.decode(raw[0]).joints.name)
        q0 = list(hand_sensors_t.decode(raw[0]).joints.position)
        cmd = joint_cmd_t()
        cmd.seq, cmd.num_joints, cmd.name, cmd.position = 0, len(names), names, q0
        bus.publish("DMPL_JOINT_CMD", cmd)
        bus.wait_for(lambda: {hand_sensors_t.decode(d).seq for d in raw} >= {1, 2, 3}, 5,
                     "ticks 1 to 3")
        bus.spin(0.05)
        self.assertEqual(max(hand_sensors_t.decode(d).seq for d in raw), delay + 1)

    def test_a_paused_simulator_keeps_the_command_until_resumed(self):
        sim, bus, states, answer = self.start(1)
        names, q0 = list(states[0].name), list(states[0].position)

        def control(command):
            c = sim_control_t()
            c.seq, c.command, c.reason = -1, command, "test"
            bus.publish("DMPL_SIM_CONTROL", c)

        answer(0, q0)
        control(sim_control_t.PAUSE)
        bus.spin(0.1)
        cmd = joint_cmd_t()
        cmd.seq, cmd.num_joints, cmd.name, cmd.position = 1, len(names), names, q0
        bus.publish("DMPL_JOINT_CMD", cmd)
        bus.spin(0.5)  # longer than run.tick_timeout_s: a pause is no fault
        self.assertEqual(len(states), 3, "stepped while paused")
        control(sim_control_t.RESUME)
        bus.wait_for(lambda: len(states) > 3, 5, "tick 3 after the resume")
        self.assertEqual(states[3].seq, 3)
        answer(2, q0)
        self.assertFalse(any(s.faults for s in bus.received.get("DMPL_SIM_STATUS", [])))

    def test_lockstep_commands_rejections_and_faults(self):
        sim, bus, states, answer = self.start(0)
        names = list(states[0].name)
        q0 = list(states[0].position)

        # A stale command (wrong seq) does not step.
        stale = joint_cmd_t()
        stale.seq, stale.num_joints, stale.name, stale.position = 7, len(names), names, q0
        bus.publish("DMPL_JOINT_CMD", stale)
        bus.spin(0.1)
        self.assertEqual(len(states), 1)
        for k in range(5):
            answer(k, q0)
        bent = list(q0)
        bent[names.index("M_j1")] = 1.0
        bad_nan = list(bent)
        bad_nan[names.index("F_j2")] = math.nan
        answer(5, bad_nan)                   # rejected: the previous targets stay
        bad_limit = list(bent)
        bad_limit[names.index("M_j1")] = 9.0
        answer(6, bad_limit)                 # rejected
        for k in range(7, 60):
            answer(k, q0)
        m1 = names.index("M_j1")
        self.assertTrue(all(abs(s.position[m1] - q0[m1]) < 0.01 for s in states),
                        "a rejected command reached the physics")
        bus.wait_for(lambda: any(s.rejected_commands == 2 for s in
                                 bus.received.get("DMPL_SIM_STATUS", [])), 5,
                     "2 rejected commands reported")
        # Stop answering: faults with the seq, then the simulator gives up (exit 4).
        code = sim.wait(timeout=10)
        self.assertEqual(code, 4)
        bus.spin(0.1)
        faults = [s for s in bus.received["DMPL_SIM_STATUS"] if s.faults > 0]
        self.assertTrue(faults)
        self.assertIn("no JOINT_CMD for seq 60", faults[-1].last_fault)

    def check_error(self, config_text, expected, urdf=None):
        if urdf is not None:
            config_text += f"hand: {{urdf: {write(urdf, '.urdf')}}}\n"
        path = write(config_text)
        r = subprocess.run([os.path.join(os.environ["DMPL_BUILD_DIR"], "bin", "dmpl_sim"),
                            "--config", path], capture_output=True, text=True, timeout=30)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(expected, r.stderr)
        return r.stderr

    def test_bad_configs_and_urdfs(self):
        err = self.check_error("sim: {durration_s: 3}\n", "unknown key 'sim.durration_s'")
        self.assertIn(".yaml", err)  # names the file
        self.check_error("object: {mass: 0}\n", "key 'object.mass': must be > 0")
        self.check_error("object: {shape: torus}\n", "unknown shape 'torus'")
        self.check_error("sim: {servo: {kp: [1, 2]}}\n", "kp and kd")
        self.check_error("sim: {command_delay_ticks: -1}\n",
                         "key 'sim.command_delay_ticks': must be in [0, 100]")
        self.check_error("hand: {urdf: /nonexistent.urdf}\n", "does not exist")
        # The loop's period, which the controller uses, is the simulator's tick.
        self.check_error("sim: {steps_per_tick: 2}\n", "key 'run.tick_s': 0.001000 s, but the "
                         "simulator's tick (sim.physics.time_step x sim.steps_per_tick) is 0.002")
        self.check_error("run: {tick_s: 0}\n", "key 'run.tick_s': must be in (0, 0.1], got 0")
        link = ('<link name="{0}"><inertial><mass value="{1}"/><inertia ixx="1e-5" iyy="1e-5" '
                'izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>')
        robot = ('<?xml version="1.0"?><robot name="r">' + link.format("palm", 1) +
                 link.format("T_tip", "{mass}") + '<joint name="j" type="{type}"><parent '
                 'link="palm"/><child link="T_tip"/><axis xyz="0 0 1"/><limit lower="-1" '
                 'upper="1" effort="1" velocity="1"/></joint></robot>')
        self.check_error("", "joint 'j' is floating", robot.format(mass=1, type="floating"))
        self.check_error("", "non-positive mass", robot.format(mass=-1, type="revolute"))


if __name__ == "__main__":
    sys.exit(unittest.main())
