"""tools/dmpl compare: sweeps side by side, case by case (the arms of a lever measured against
the code as it is), and its refusals."""
import json
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

from dmpl_tools import compare


def trial(case, seed, **kw):
    row = {"case": case, "seed": seed, "status": "success", "goals_reached": None,
           "rotation_total_rad": 6.45, "rotation_rate_rad_s": 0.5, "sim_time_s": 13.0,
           "recoveries": 0}
    row.update(kw)
    return row


def write_sweep(rows):
    out = Path(tempfile.mkdtemp(prefix="dmpl_compare_"))
    (out / "sweep.json").write_text(json.dumps({"summaries": rows}))
    return out


AS_IS = [trial("nominal", 1, goals_reached=20, time_per_goal_median_s=4.5),
         trial("nominal", 2, goals_reached=20, time_per_goal_median_s=4.9),
         trial("cube", 1, status="failed", rotation_total_rad=1.8, sim_time_s=9.0),
         trial("cube", 2, status="failed", rotation_total_rad=1.9, sim_time_s=9.5),
         trial("sphere", 1), trial("sphere", 2, rotation_rate_rad_s=0.6)]
LEVER = [trial("nominal", 1, goals_reached=20, time_per_goal_median_s=4.5),
         trial("nominal", 2, goals_reached=7, time_per_goal_median_s=5.3, status="failed"),
         trial("cube", 1, status="failed", rotation_total_rad=1.8, sim_time_s=9.0),
         trial("cube", 2, status="failed", rotation_total_rad=1.9, sim_time_s=9.5),
         trial("cube", 3, status="error", problems=["the simulator died"]),
         trial("sphere", 1), trial("sphere", 2, rotation_rate_rad_s=0.6, sim_time_s=12.0),
         trial("egg", 1)]


class CompareTest(unittest.TestCase):
    def test_arms_side_by_side(self):
        table = compare.compare([compare.load_sweep(write_sweep(AS_IS)),
                                 compare.load_sweep(write_sweep(LEVER))])
        self.assertEqual(list(table), ["nominal", "cube", "sphere", "egg"])
        first, lever = table["nominal"]
        self.assertEqual((first["goals_total"], first["goals"]), (40, [20, 20]))
        self.assertAlmostEqual(first["time_per_goal_median_s"], 4.7)
        self.assertEqual((lever["goals_total"], lever["as_first"]), (27, False))
        # The cube ran as the first on the seeds both have; the lever's third seed is not set
        # beside nothing.
        self.assertTrue(table["cube"][1]["as_first"])
        self.assertEqual(table["cube"][1]["seeds"], [1, 2])
        sphere = table["sphere"]
        self.assertEqual((sphere[0]["succeeded"], sphere[0]["runs"]), (2, 2))
        self.assertAlmostEqual(sphere[0]["rate_median_rad_s"], 0.55)
        self.assertFalse(sphere[1]["as_first"])  # the same outcome, in another time
        self.assertIsNone(table["egg"][0])  # only the lever ran it: shown, beside nothing
        self.assertEqual((table["egg"][1]["succeeded"], table["egg"][1]["as_first"]), (1, False))
        text = compare.markdown(table, ["as is", "lever"]).splitlines()
        self.assertEqual(text[0], "| case | as is | lever |")
        self.assertIn("| nominal | 40 (20, 20), 4.70 s/goal | 27 (20, 7), 4.90 s/goal |", text)
        self.assertIn("| cube | 0/2 (1.8, 1.9) | = |", text)
        self.assertTrue(text[-1].startswith("| egg | - | 1/1 ("), text[-1])

    def test_errored_trials_are_counted_with_their_reason(self):
        table = compare.compare([compare.load_sweep(write_sweep(LEVER))])
        cube = table["cube"][0]
        self.assertEqual((cube["errors"], cube["runs"]), (1, 2))
        self.assertEqual(cube["error_reasons"], ["the simulator died"])
        self.assertIn("1 errored", compare.text(cube))

    def test_the_command_and_its_refusals(self):
        a, b = write_sweep(AS_IS), write_sweep(LEVER)
        report = Path(tempfile.mkdtemp()) / "cmp.json"
        run = [sys.executable, "-m", "dmpl_tools.compare"]
        done = subprocess.run(run + [str(a), str(b), "--names", "as is,lever", "--json",
                                     str(report)], capture_output=True, text=True, timeout=60)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("| cube | 0/2 (1.8, 1.9) | = |", done.stdout)
        self.assertEqual(json.loads(report.read_text())["arms"], ["as is", "lever"])
        bad = Path(tempfile.mkdtemp())
        (bad / "sweep.json").write_text("{not json")
        other = Path(tempfile.mkdtemp())
        (other / "sweep.json").write_text(json.dumps({"trials": 3}))
        for argv, message in [([str(a / "missing")], "cannot read"),
                              ([str(bad)], "is not JSON"),
                              ([str(other)], "is not a sweep's output"),
                              ([str(a), str(b), "--names", "one"], "gives 1 names for 2")]:
            done = subprocess.run(run + argv, capture_output=True, text=True, timeout=60)
            self.assertEqual(done.returncode, 2, argv)
            self.assertIn(message, done.stderr.strip().splitlines()[-1])
            self.assertNotIn("Traceback", done.stderr)
            self.assertEqual(done.stdout, "")


if __name__ == "__main__":
    sys.exit(unittest.main())
