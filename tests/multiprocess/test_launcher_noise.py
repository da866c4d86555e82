"""The launcher starts a set with dmpl_noise; sensed messages arrive with the right seq and
statistics; a killed process with auto_respawn comes back; stopping leaves no process behind."""
import math
import os
import signal
import statistics
import sys
import unittest

import mp
from dmpl import object_pose_t, process_status_t, tactile_t, fingertip_contact_t

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


class LauncherNoiseTest(unittest.TestCase):
    def test_set(self):
        bus = mp.Bus()
        bus.listen("DMPL_PROCESS_STATUS", process_status_t)
        bus.listen("DMPL_OBJECT_POSE", object_pose_t)
        bus.listen("DMPL_TACTILE", tactile_t)
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

            # Lockstep-style: publish truth k, wait for sensed k.
            xs, forces = [], []
            for k in range(N):
                bus.publish("DMPL_OBJECT_POSE_TRUE", truth_pose(k))
                bus.publish("DMPL_TACTILE_TRUE", truth_tactile(k))
                bus.wait_for(lambda: len(bus.received.get("DMPL_OBJECT_POSE", [])) > k and
                             len(bus.received.get("DMPL_TACTILE", [])) > k, 5, f"sensed seq {k}")
                pose = bus.received["DMPL_OBJECT_POSE"][k]
                self.assertEqual(pose.seq, k)
                self.assertEqual(bus.received["DMPL_TACTILE"][k].seq, k)
                xs.append(pose.position[0])
                forces.append(bus.received["DMPL_TACTILE"][k].fingers[0].force_n)
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
            count = len(bus.received["DMPL_OBJECT_POSE"])
            bus.publish("DMPL_OBJECT_POSE_TRUE", truth_pose(N))
            bus.wait_for(lambda: len(bus.received["DMPL_OBJECT_POSE"]) > count, 5,
                         "sensed pose after respawn")
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
