"""Issue 5: the paper's experiments as full process sets (sim, noise, IK, controller, supervisor)
run by tools/dmpl run, with assertions on summary.json; variants (another radius, another axis)
in one-process mode, which gives the same results faster. The finger-gaiting experiments run a
shorter rotation here (one cycle); the whole turns belong to sweeps (tools/dmpl sweep)."""
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import yaml

import mp
from dmpl_tools.run import run_experiment

EXP = mp.ROOT + "/configs/experiments/"
BIN = Path(os.environ.get("DMPL_BUILD_DIR", Path(mp.ROOT) / "build")) / "bin"


def run(name, *sets, one_process=False, seed=1):
    summary, _ = run_experiment(EXP + name + ".yaml", tempfile.mkdtemp(prefix="dmpl_exp_"),
                                seed=seed, sets=sets, echo=False, one_process=one_process)
    return summary


class ExperimentsTest(unittest.TestCase):
    def check_fig8(self, s):
        self.assertEqual(s["status"], "success", s.get("problems"))
        self.assertLess(s["final_orientation_error_rad"], 0.02)
        self.assertEqual(s["contacts_lost"], 0)
        self.assertFalse(s["object_dropped"])
        self.assertEqual(s["log_missing_ticks"], 0)

    def test_fig8_sphere(self):
        self.check_fig8(run("fig8_sphere"))

    def test_fig8_cylinder(self):
        self.check_fig8(run("fig8_cylinder"))

    def test_fig8_variants(self):
        self.check_fig8(run("fig8_sphere", "object.radius=0.03", one_process=True))
        self.check_fig8(run("fig8_sphere", "task.axis=y", one_process=True))

    def test_fig9_explore(self):
        for s in (run("fig9_explore"), run("fig9_explore", "object.radius=0.03", one_process=True)):
            self.assertEqual(s["status"], "success", s.get("problems"))
            self.assertFalse(s["object_dropped"])
            self.assertLess(s["exploration_force_rms_error_n"], 0.05)
            self.assertAlmostEqual(s["exploration_force_mean_n"], 0.1, delta=0.03)

    def test_only_the_simulator_is_given_the_object(self):
        # The hand's own software (noise, IK, controller, supervisor) gets the config without its
        # `object` section: it cannot read the object's shape, size, mass or friction.
        out = Path(tempfile.mkdtemp(prefix="dmpl_blind_"))
        summary, _ = run_experiment(EXP + "fig8_sphere.yaml", out, echo=False,
                                    sets=["object.mass=0.07"])
        self.assertEqual(summary["status"], "success", summary.get("problems"))
        sensing = yaml.safe_load((out / "config.sensing.yaml").read_text())
        self.assertNotIn("object", sensing)
        self.assertEqual(yaml.safe_load((out / "config.yaml").read_text())["object"]["mass"], 0.07)
        for p in sensing["processes"]:
            given = p["args"][p["args"].index("--config") + 1]
            self.assertEqual(given, "${config}" if p["name"] == "dmpl_sim" else
                             "${sensing_config}", p["name"])
        for node in ("dmpl_controller", "dmpl_supervisor"):
            r = subprocess.run([str(BIN / node), "--config", str(out / "config.sensing.yaml"),
                                "--print-config"], capture_output=True, text=True, timeout=30)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertNotIn("object:", r.stdout)
            self.assertNotIn("0.07", r.stdout)

    def test_fig10_gait_short(self):
        # Two steps of the configured gait (about x: R, then M explore while the other three turn
        # the object 15 deg) on the sphere and the cylinder, and of the paper's (R explores, then
        # TFM turn 10 deg; then M while TFR turn) on the sphere.
        for s in (run("fig10_gait_sphere", "task.angle=0.5"),
                  run("fig10_gait_cylinder", "task.angle=0.5", one_process=True),
                  run("fig10_gait_paper", "task.angle=0.35", "task.turn=three",
                      "task.step=0.17453292519943295", one_process=True)):
            self.assertEqual(s["status"], "success", s.get("problems"))
            self.assertFalse(s["object_dropped"])
            self.assertEqual(s["contacts_lost"], 0)
            self.assertGreater(s["rotation_total_rad"], s["rotation_commanded_rad"] - 0.05)
            self.assertGreater(s["rotation_commanded_rad"], 0.34)
            self.assertGreaterEqual(s["regrasps"], 2)


if __name__ == "__main__":
    sys.exit(unittest.main())
