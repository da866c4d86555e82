"""The launcher starts a set with dmpl_noise; sensed messages arrive with the right seq and
statistics; a killed process with auto_respawn comes back; stopping leaves no process behind."""
import math
import os
import signal
import statistics
import sys
import unittest

import mp
from dmpl import (fingertip_contact_t, hand_sensors_t, joint_state_t, object_pose_t,
                  process_status_t, tactile_t)

SET = os.path.join(mp.ROOT, "configs/sets/noise.yaml")
SIGMA = 0.005   # configs/sets/noise_params.yaml
FORCE_SIGMA = 0.02
N = 2000


def truth_pose(seq):
    m = object_pose_t()
    m.utime, m.seq, m.valid = seq * 1000, seq, True
    m.position = [0.05, 0.0, 0.1]
    m.orientation = [1.0, 0.0, 0.0, 0.0]
    return m


def truth_tactile(seq):
    m = tactile_t()
    m.utime, m.seq = seq * 1000, seq
    f = fingertip_contact_t()
    f.finger, f.in_contact, f.force_n, f.num_points = "T", True, 0.5, 1
    f.position, f.normal = [0.0, 0.0, 0.1], [1.0, 0.0, 0.0]
    m.fingers, m.num_fingers = [f], 1
    return m


def truth(seq):
    m = hand_sensors_t()
    m.utime, m.seq = seq * 1000, seq
    m.joints = joint_state_t()
    m.joints.utime, m.joints.seq = m.utime, seq
    m.object, m.tactile = truth_pose(seq), truth_tactile(seq)
    return m


class LauncherNoiseTest(unittest.TestCase):
    def test_set(self):
        bus = mp.Bus()
        bus.listen("DMPL_PROCESS_STATUS", process_status_t)
        bus.listen("DMPL_SENSORS", hand_sensors_t)
        proc, run_dir = mp.launch(SET)
        pids = set()
        try:
            def noise_info():
                statuses = bus.received.get("DMPL_PROCESS_STATUS", [])
                if not statuses:
                    return None
                return next(p for p in statuses[-1].processes if p.name == "dmpl_noise")

            bus.wait_for(lambda: noise_info() and noise_info().state == "running", 20,
                         "dmpl_noise running")
            first_pid = noise_info().pid
            pids.add(first_pid)

            # Lockstep-style: publish truth k, wait for sensed k (while it waits, the node sends
            # its last answers again: the same ones, kept once here).
            xs, forces = [], []

            def sensed_by_seq():
                return {m.seq: m for m in bus.received.get("DMPL_SENSORS", [])}
            for k in range(N):
                bus.publish("DMPL_SENSORS_TRUE", truth(k))
                bus.wait_for(lambda: k in sensed_by_seq(), 5, f"sensed seq {k}")
                sensed = sensed_by_seq()[k]
                self.assertEqual(sensed.seq, k)
                self.assertEqual(sensed.object.seq, k)
                self.assertEqual(sensed.tactile.seq, k)
                xs.append(sensed.object.position[0])
                forces.append(sensed.tactile.fingers[0].force_n)
            for values, mean, sigma in ((xs, 0.05, SIGMA), (forces, 0.5, FORCE_SIGMA)):
                m, s = statistics.fmean(values), statistics.stdev(values)
                self.assertLess(abs(m - mean), 3 * sigma / math.sqrt(N))
                self.assertLess(abs(s - sigma), 3 * sigma / math.sqrt(2 * (N - 1)))

            # Kill it: auto_respawn brings it back with a new pid.
            os.kill(first_pid, signal.SIGKILL)
            bus.wait_for(lambda: noise_info().restarts == 1 and noise_info().state == "running"
                         and noise_info().pid not in (0, first_pid), 20, "dmpl_noise respawned")
            pids.add(noise_info().pid)
            # It works again.
            bus.publish("DMPL_SENSORS_TRUE", truth(N))
            bus.wait_for(lambda: N in sensed_by_seq(), 5, "sensed tick after respawn")
        finally:
            code = mp.stop(proc)
        self.assertEqual(code, 0, "a clean stop exits 0")
        for pid in pids:
            self.assertFalse(mp.pid_alive(pid), f"pid {pid} survived the stop")
        # No process of ours is left in any process group we started.
        self.assertTrue(os.path.getsize(os.path.join(run_dir, "run.lcmlog")) > 0)
        with open(os.path.join(run_dir, "dmpl_noise.log")) as f:
            self.assertIn("started", f.read())


if __name__ == "__main__":
    sys.exit(unittest.main())
