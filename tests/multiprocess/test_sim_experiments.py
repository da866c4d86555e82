"""tools/dmpl run on the simulator's experiments (issue 3): the static grasp holds, the drop
drops, and the same seed twice gives the same metrics."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import mp

WEIGHT = 0.05 * 9.81  # the paper's sphere


def run(config, *extra):
    out = tempfile.mkdtemp(prefix="dmpl_run_")
    r = subprocess.run([sys.executable, "-m", "dmpl_tools.run", config, "--out", out, "--quiet",
                        *extra], cwd=mp.ROOT, capture_output=True, text=True, timeout=600)
    path = os.path.join(out, "summary.json")
    if not os.path.exists(path):
        raise AssertionError(f"no summary.json\n{r.stdout}\n{r.stderr}")
    with open(path) as f:
        return json.load(f), r


class SimExperimentsTest(unittest.TestCase):
    def test_static_grasp_holds_and_is_reproducible(self):
        a, r = run("configs/experiments/static_grasp.yaml", "--seed", "3")
        self.assertEqual(a["status"], "success", r.stdout + r.stderr)
        self.assertFalse(a["object_dropped"])
        # 1 s after release, over the next 5 s: < 0.1 mm/s and < 1 mm in all.
        self.assertLess(a["drift_rate_m_per_s"], 1e-4)
        self.assertLess(a["max_position_drift_m"], 1e-3)
        self.assertGreater(a["grip_force_total_n"], WEIGHT)       # it is held by the fingers...
        self.assertLess(a["grip_force_total_n"], 10 * WEIGHT)     # ...without crushing it
        self.assertEqual(a["contacts_lost"], 0)
        self.assertEqual(a["lockstep_faults"], 0)
        b, _ = run("configs/experiments/static_grasp.yaml", "--seed", "3")
        for key in ("max_position_drift_m", "rotation_total_rad", "grip_force_total_n",
                    "final_orientation_error_rad", "sim_time_s"):
            self.assertEqual(a[key], b[key], key)

    def test_drop(self):
        s, r = run("configs/experiments/drop.yaml")
        self.assertTrue(s["object_dropped"], r.stdout)
        self.assertEqual(s["status"], "success")  # drop.yaml allows the drop

    def test_bad_experiment_is_rejected_before_anything_starts(self):
        s = subprocess.run([sys.executable, "-m", "dmpl_tools.run",
                            "configs/experiments/static_grasp.yaml", "--set", "object.mass=-1",
                            "--out", tempfile.mkdtemp()], cwd=mp.ROOT, capture_output=True,
                           text=True, timeout=60)
        self.assertEqual(s.returncode, 2)
        self.assertIn("object.mass", s.stderr)
        s = subprocess.run([sys.executable, "-m", "dmpl_tools.run",
                            "configs/experiments/static_grasp.yaml", "--set", "sim.servo.kq=1",
                            "--out", tempfile.mkdtemp()], cwd=mp.ROOT, capture_output=True,
                           text=True, timeout=60)
        self.assertEqual(s.returncode, 2)
        self.assertIn("unknown key 'sim.servo.kq'", s.stderr)


if __name__ == "__main__":
    sys.exit(unittest.main())
