"""Issue 6: the main job's pieces. The demo experiment (a shorter rotation) runs and its report
files exist and are valid images; one-process and multi-process lockstep runs with the same seed
give the same metrics, with the actuation delay in the two-CPU layout and without it; replaying a recorded log's sensed channels and tasks into a fresh
controller reproduces its recorded commands; a sweep of 3 seeds completes and its table matches
the individual runs."""
import json
import os
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

import mp
from dmpl_tools.process_set import SetError
from dmpl_tools.run import loop_layout, run_experiment
from dmpl_tools.sweep import run_sweep

ROOT = Path(mp.ROOT)
FIG8 = ROOT / "configs/experiments/fig8_sphere.yaml"
SHORT = ["task.angle=0.1"]
DELAYED = ["sim.command_delay_ticks=1"]
METRIC_KEYS = ["object_dropped", "rotation_total_rad", "final_orientation_error_rad",
               "max_position_drift_m", "grip_force_total_n", "contacts_lost", "regrasps",
               "sim_time_s", "status"]


class MainJobTest(unittest.TestCase):
    def test_demo_report(self):
        out = Path(tempfile.mkdtemp(prefix="dmpl_demo_"))
        r = subprocess.run([sys.executable, "-m", "dmpl_tools.demo", "--out", str(out),
                            "--set", "task.angle=0.2"], cwd=mp.ROOT, capture_output=True,
                           text=True, timeout=600)
        self.assertIn("report:", r.stdout, r.stdout + r.stderr)
        self.assertTrue((out / "summary.json").exists())
        self.assertTrue((out / "run.lcmlog").stat().st_size > 0)
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.image as mpimg
        for png in ["fig8a_orientation.png", "fig8b_position.png", "fig9_exploration.png",
                    "fig10_forces.png", "statechart.png"]:
            path = out / "report" / png
            self.assertEqual(path.read_bytes()[:8], b"\x89PNG\r\n\x1a\n", png)
            image = mpimg.imread(path)
            self.assertGreater(image.shape[0], 100, png)
            self.assertGreater(image.std(), 0.01, f"{png} is blank")
        report = (out / "report" / "report.md").read_text()
        self.assertIn("rotation_total_rad", report)
        summary = json.loads((out / "summary.json").read_text())
        self.assertEqual(summary["status"], "success", summary.get("problems"))
        self.assertGreater(summary["rotation_total_rad"], 0.15)
        self.assertIn("[demo] sim", r.stderr, "progress is shown while it runs")

    def test_one_process_equals_multi_process(self):
        # With the actuation delay the simulator runs a tick ahead of the nodes, in parallel in
        # the two-CPU layout; without it nothing overlaps. Either way: the one-process result.
        cpus, pins = loop_layout()
        for delay, layout in ((1, {"cpus": cpus, "pins": pins}), (0, {})):
            sets = [*SHORT, f"sim.command_delay_ticks={delay}"]
            a, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=7, sets=sets, echo=False,
                                  **layout)
            b, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=7, sets=sets, echo=False,
                                  one_process=True)
            for key in METRIC_KEYS:
                self.assertEqual(a[key], b[key], f"{key}, delay {delay}")
            self.assertEqual(a["status"], "success")
        # One process on one CPU steps the physics on the nodes' thread, on two on its own
        # (sim.background_step): the same run.
        c, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=7, sets=[*SHORT, *DELAYED],
                              echo=False, one_process=True, cpus=[-1])
        d, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=7, sets=[*SHORT, *DELAYED],
                              echo=False, one_process=True, cpus=[0, -1] if cpus else None)
        for key in METRIC_KEYS:
            self.assertEqual(c[key], d[key], f"{key}, one process on one CPU or two")

    def test_with_mujoco_one_process_equals_multi_process(self):
        # The second engine (sim.engine: mujoco) is as deterministic as the first.
        cpus, pins = loop_layout()
        sets = [*SHORT, "sim.engine=mujoco"]
        a, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=7, sets=sets, echo=False,
                              cpus=cpus, pins=pins)
        b, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=7, sets=sets, echo=False,
                              one_process=True)
        for key in METRIC_KEYS:
            self.assertEqual(a[key], b[key], key)
        self.assertEqual(a["status"], "success")

    def test_pinning_a_process_the_set_lacks_is_an_error(self):
        with self.assertRaisesRegex(SetError, r"--pin dmpl_simm: the experiment has no such "
                                    r"process \(it has dmpl_noise, .*dmpl_sim\)"):
            run_experiment(FIG8, tempfile.mkdtemp(), sets=SHORT, echo=False,
                           pins={"dmpl_simm": [0]})

    def test_replay_reproduces_the_controller(self):
        summary, out = run_experiment(FIG8, tempfile.mkdtemp(), seed=3, sets=SHORT, echo=False,
                                      one_process=True)
        self.assertEqual(summary["status"], "success")
        controller = subprocess.Popen(
            [os.path.join(os.environ["DMPL_BUILD_DIR"], "bin", "dmpl_controller"), "--config",
             str(out / "config.yaml")], cwd=mp.ROOT)
        try:
            time.sleep(0.5)
            r = subprocess.run([sys.executable, "-m", "dmpl_tools.replay", str(out / "run.lcmlog"),
                                "--channels", "DMPL_(SENSORS|TASK)$",
                                "--answer", "DMPL_FINGER_TARGETS", "--compare"], cwd=mp.ROOT,
                               capture_output=True, text=True, timeout=300)
        finally:
            controller.terminate()
            controller.wait()
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn(" 0 differ", r.stdout)
        self.assertIn(" 0 missing", r.stdout)

    def test_sweep_matches_individual_runs(self):
        out = Path(tempfile.mkdtemp(prefix="dmpl_sweep_"))
        trials, rate = run_sweep(FIG8, 3, 2, out, sets=SHORT)
        doc = json.loads((out / "sweep.json").read_text())
        self.assertEqual(doc["trials"], 3)
        self.assertEqual(doc["success_rate"], rate)
        self.assertTrue((out / "sweep.md").exists())
        for s in doc["summaries"]:
            single, _ = run_experiment(FIG8, tempfile.mkdtemp(), seed=s["seed"], sets=SHORT,
                                       echo=False, one_process=True)
            for key in METRIC_KEYS:
                self.assertEqual(s[key], single[key], f"seed {s['seed']} {key}")
        table = (out / "sweep.md").read_text()
        for s in doc["summaries"]:
            self.assertIn(f"| {s['seed']} | {s['status']} |", table)


if __name__ == "__main__":
    sys.exit(unittest.main())
