"""Issue 29: a cube turned end over end (about y) by the process set: the thumb's contact crosses
an edge onto the next face without the grasp being lost, the supervisor's edge detector (in
Blackboard::LearnSurface, replayed from the log by dmpl_surface) finds that edge where the cube
has one, and the report's faces (detected by touch) are the true ones."""
import json
import os
import re
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

import mp
from dmpl_tools.report import make_report
from dmpl_tools.run import run_experiment

GAIT = mp.ROOT + "/configs/experiments/fig10_gait_sphere.yaml"
BIN = Path(os.environ.get("DMPL_BUILD_DIR", Path(mp.ROOT) / "build")) / "bin"
HALF = 0.025  # the 5 cm cube's half edge


class EdgesTest(unittest.TestCase):
    def test_the_thumb_crosses_an_edge_of_a_cube_and_it_is_felt(self):
        summary, out = run_experiment(
            GAIT, tempfile.mkdtemp(prefix="dmpl_edges_"), seed=1, echo=False, record="analysis",
            sets=["object.shape=box", "object.size=[0.05,0.05,0.05]", "task.axis=y",
                  "task.angle=1.0"])
        self.assertEqual(summary["status"], "success", summary.get("problems"))
        self.assertEqual(summary["contacts_lost"], 0)
        surface = subprocess.run([str(BIN / "dmpl_surface"),
                                  str(out / "run.lcmlog")], capture_output=True, text=True,
                                 timeout=120, check=True)
        edges = json.loads(surface.stdout)["edges"]
        thumb = [e for e in edges if e["finger"] == "T"]
        self.assertTrue(thumb, edges)
        # On one of the cube's edges along y (|x| and |z| both at the half edge, object frame:
        # the pose estimate carries 0.5 cm of noise, low-passed), between faces at right angles.
        p = np.array(thumb[0]["point"])
        self.assertLess(abs(abs(p[0]) - HALF), 0.006, p)
        self.assertLess(abs(abs(p[2]) - HALF), 0.006, p)
        self.assertGreater(thumb[0]["angle_rad"], 0.5)
        n0, n1 = np.array(thumb[0]["normal_before"]), np.array(thumb[0]["normal_after"])
        self.assertLess(abs(n0[1]) + abs(n1[1]), 0.2)  # both across the edge's direction y
        report = make_report(out / "run.lcmlog", Path(tempfile.mkdtemp()) / "report")
        agree = re.search(r"\| face detected = true face \| (\d+) % of the contact time",
                          report.read_text())
        self.assertIsNotNone(agree)
        self.assertGreaterEqual(int(agree.group(1)), 95)


if __name__ == "__main__":
    sys.exit(unittest.main())
