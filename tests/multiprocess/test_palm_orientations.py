"""Issue 30: the hand in any orientation. Gravity reaches the controller only through the palm's
IMU (hand_sensors_t.gravity); the grip fingers carry the weight (controller.carry_offset_m) and
their pushes hold it up where friction cannot (controller.normals_aim.friction_along_gravity).
Palm down, a heavy sphere goes through a regrasp cycle without losing a contact (and without
the carry it drops); sideways, one whole regrasp cycle, and with a heavy sphere too (without
the pushes holding it up it drops); and a palm that turns 90 deg while the sphere is turned a
full revolution."""
import math
import sys
import tempfile
import unittest

import mp
from dmpl_tools.run import run_experiment

EXP = mp.ROOT + "/configs/experiments/"


def run(config, *sets, one_process=False):
    summary, _ = run_experiment(EXP + config, tempfile.mkdtemp(prefix="dmpl_palm_"), echo=False,
                                one_process=one_process, sets=list(sets))
    return summary


class PalmOrientationsTest(unittest.TestCase):
    def check_turned(self, s, angle, regrasps):
        self.assertEqual(s["status"], "success", s.get("problems"))
        self.assertFalse(s["object_dropped"])
        self.assertEqual(s["contacts_lost"], 0)
        self.assertGreater(s["rotation_total_rad"], angle - 0.05)
        self.assertGreaterEqual(s["regrasps"], regrasps)

    def test_palm_down_a_heavy_sphere_hangs_in_the_grip_through_its_explores(self):
        # The process set (multi-process), 200 g hanging palm down, one regrasp cycle (R, M,
        # F, T explore while the others turn it). The grip carries its weight: it sinks less
        # than 1.5 cm.
        s = run("palm_down.yaml", "object.mass=0.2", "task.angle=1.1")
        self.check_turned(s, 1.1, 4)
        self.assertLess(s["max_position_drift_m"], 0.015)
        # Held only 4 mm behind their tips, the same grip lets it sink out of the hand within
        # the cycle (docs/benchmarks.md: 0 of 3 full turns).
        weak = run("palm_down.yaml", "object.mass=0.2", "task.angle=1.1",
                   "controller.carry_offset_m=0", one_process=True)
        self.assertEqual(weak["status"], "failed")
        self.assertGreater(weak["max_position_drift_m"], 0.015)

    def test_sideways_one_regrasp_cycle(self):
        # Every finger explores once (R, M, F, T), the palm's normal horizontal.
        s = run("palm_side.yaml", "task.angle=1.1")
        self.check_turned(s, 1.1, 4)

    def test_sideways_a_heavy_sphere_is_held_up_by_the_pushes(self):
        # 200 g sideways, one regrasp cycle: the thumb below carries the weight with its push
        # and the finger on top eases (controller.normals_aim.friction_along_gravity), where
        # the fingers at the sides, one of them exploring, cannot hold it by friction.
        s = run("palm_side.yaml", "object.mass=0.2", "task.angle=1.1", one_process=True)
        self.check_turned(s, 1.1, 4)
        # Left to friction along gravity, the thumb's force loop gives way under the weight and
        # the sphere drops at the first explore (docs/benchmarks.md: 0 of 10 full turns).
        left = run("palm_side.yaml", "object.mass=0.2", "task.angle=1.1",
                   "controller.normals_aim.friction_along_gravity=0", one_process=True)
        self.assertEqual(left["status"], "failed")
        self.assertTrue(left["object_dropped"])

    def test_a_turning_palm_turns_the_sphere_a_full_revolution(self):
        s = run("palm_turning.yaml", one_process=True)
        self.check_turned(s, 6.45, 20)
        # The palm went from up to sideways while the fingers turned the sphere.
        self.assertAlmostEqual(s["palm_turned_rad"], math.pi / 2, delta=0.01)
        self.assertGreater(s["rotation_rate_rad_s"], 0.4)


if __name__ == "__main__":
    sys.exit(unittest.main())
