"""Issue 4: sim + noise + IK + controller as separate processes, this test sending the task
messages (in lockstep, as the supervisor would). From a grasp on the paper's sphere, rotate
0.2 rad about x and back with 0.005 m position noise: final orientation error < 0.02 rad, no grip
contact lost, not dropped; the same for the cylinder."""
import math
import os
import sys
import tempfile
import threading
import unittest

import numpy as np

import mp
from dmpl import (controller_status_t, finger_primitive_t, heartbeat_t, sim_control_t,
                  task_cmd_t)
from dmpl_tools.logdata import quat_mul
from dmpl_tools.run import run_experiment

CONFIG = os.path.join(mp.ROOT, "configs/experiments/controller_rotate.yaml")
FINGERS = ["T", "F", "M", "R"]
MOTION_DONE = 3


def rot_x(angle):
    return np.array([math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0])


class Supervisor(threading.Thread):
    """Answers every controller report k with the task of seq k (lockstep), as dmpl_supervisor:
    a process of the run, whose identity it takes from the reports (the run's nodes take no loop
    message without it)."""

    def __init__(self):
        super().__init__(daemon=True)
        self.bus = mp.Bus()
        self.bus.subscribe("DMPL_CONTROLLER_REPORT", self.on_status)
        self.stop = False
        self.phase, self.task_id = "grip", 1
        self.start_pose = None
        self.released = False
        self.t_done = None
        self.log = []

    def task(self, run_id, seq, target=None):
        m = task_cmd_t()
        m.run_id, m.seq, m.task_id, m.name = run_id, seq, self.task_id, self.phase
        m.has_object_target = target is not None
        if target is not None:
            m.object_position, m.object_orientation = list(target[0]), list(target[1])
        for f in FINGERS:
            p = finger_primitive_t()
            p.finger, p.role, p.primitive = f, finger_primitive_t.GRIP, finger_primitive_t.COMPOSITE
            m.fingers.append(p)
        m.num_fingers = len(m.fingers)
        self.bus.publish("DMPL_TASK", m)

    def on_status(self, channel, data):
        s = controller_status_t.decode(data)
        t = s.utime * 1e-6
        # Only the task under way's: a report the controller sends again (its answer was late)
        # carries the last task's MOTION_DONE once more, which must not end this one at once.
        done = s.task_id == self.task_id and any(e.type == MOTION_DONE for e in s.events)
        target = None
        if self.phase == "grip":
            if t >= 0.2 and not self.released:
                c = sim_control_t()
                c.run_id, c.seq, c.command, c.reason = s.run_id, s.seq, sim_control_t.RELEASE, "test"
                self.bus.publish("DMPL_SIM_CONTROL", c)
                self.released = True
            if t >= 0.8:
                self.start_pose = (np.array(s.object_position), np.array(s.object_orientation))
                self.phase, self.task_id = "rotate", 2
        elif self.phase == "rotate" and done:
            self.phase, self.task_id = "back", 3
            self.log.append(("rotated", t))
        elif self.phase == "back" and done:
            self.phase, self.t_done = "hold", t
            self.log.append(("back", t))
        if self.phase == "rotate":
            target = (self.start_pose[0], quat_mul(rot_x(0.2), self.start_pose[1]))
        elif self.phase in ("back", "hold"):
            target = self.start_pose
        if self.phase == "hold" and t > self.t_done + 0.5:
            c = sim_control_t()
            c.run_id, c.seq, c.command, c.reason = s.run_id, s.seq, sim_control_t.STOP, "test done"
            self.bus.publish("DMPL_SIM_CONTROL", c)
        self.task(s.run_id, s.seq, target)

    def run(self):
        hb = heartbeat_t()
        hb.process, hb.pid, hb.state = "test_supervisor", os.getpid(), heartbeat_t.RUNNING
        while not self.stop:
            self.bus.publish("DMPL_HEARTBEAT", hb)
            for _ in range(10):
                self.bus.buses.handle(0.01)


class ControllerRotateTest(unittest.TestCase):
    def rotate(self, *sets):
        sup = Supervisor()
        sup.start()
        try:
            summary, out = run_experiment(CONFIG, tempfile.mkdtemp(prefix="dmpl_rot_"),
                                          sets=sets, echo=False)
        finally:
            sup.stop = True
        print(summary, sup.log)
        self.assertEqual([name for name, _ in sup.log], ["rotated", "back"], summary)
        self.assertEqual(summary["log_missing_ticks"], 0)
        self.assertFalse(summary["object_dropped"])
        self.assertEqual(summary["contacts_lost"], 0)
        self.assertLess(summary["final_orientation_error_rad"], 0.02)
        self.assertEqual(summary["status"], "success", summary.get("problems"))

    def test_sphere(self):
        self.rotate()

    def test_cylinder(self):
        # Standing on its end, axis along the palm normal (x), turned about that axis.
        self.rotate("object.shape=cylinder", "object.rpy=[0, 1.5707963267948966, 0]")


if __name__ == "__main__":
    sys.exit(unittest.main())
