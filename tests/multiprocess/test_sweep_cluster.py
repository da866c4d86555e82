"""Issue 19: sweeps on an existing distributed engine. A sweep's trials submitted to a Dask
scheduler (here a LocalCluster of two worker processes, as `dask-scheduler` and `dask-worker`
would run on a lab's machines) give the results of the same sweep run here, and an interrupted
sweep resumes, skipping the trials it finished."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import mp
from dmpl_tools.sweep import _worker_has_project, run_sweep
from dmpl_tools.sweep import main as sweep_main

EXP = mp.ROOT + "/configs/experiments/fig8_sphere.yaml"
# What differs between two runs of one trial: the machine's time, and whether it was resumed.
NOT_RESULTS = {"wall_time_s", "realtime_factor", "resumed"}


def results(summary):
    return {k: v for k, v in summary.items() if k not in NOT_RESULTS}


class SweepClusterTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = Path(tempfile.mkdtemp(prefix="dmpl_cluster_"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_a_cluster_sweep_gives_the_local_results_and_resumes(self):
        from distributed import LocalCluster
        local, local_rate = run_sweep(EXP, 2, 2, self.tmp / "local")
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster:
            address = cluster.scheduler_address
            clustered, rate = run_sweep(EXP, 2, 2, self.tmp / "cluster", cluster=address)
            self.assertEqual(rate, local_rate)
            self.assertEqual([results(s) for s in clustered], [results(s) for s in local])
            # Interrupted after the first trial: the second's summary is gone.
            (self.tmp / "cluster" / "seed2" / "summary.json").unlink()
            again, _ = run_sweep(EXP, 2, 2, self.tmp / "cluster", cluster=address, resume=True)
        self.assertTrue(again[0].get("resumed"))
        self.assertNotIn("resumed", again[1])
        self.assertEqual([results(s) for s in again], [results(s) for s in local])
        # A trial of another config (here another seed range) is not taken for a finished one.
        shifted, _ = run_sweep(EXP, 1, 1, self.tmp / "cluster", first_seed=1, resume=True,
                               sets=["noise.object_position_sigma=0.001"])
        self.assertNotIn("resumed", shifted[0])

    def test_a_slurm_array_sweep_gives_the_local_results(self):
        # The script sbatch would run, run here once per array task; --collect gathers.
        out, script = self.tmp / "slurm", self.tmp / "sweep.sbatch"
        self.assertEqual(sweep_main([EXP, "--seeds", "2", "--out", str(out),
                                     "--slurm-script", str(script)]), 0)
        text = script.read_text()
        self.assertIn("#SBATCH --array=0-1", text)
        subprocess.run(["bash", "-n", str(script)], check=True)
        for task in ("0", "1"):
            subprocess.run(["bash", str(script)], check=True, capture_output=True,
                           env=dict(os.environ, SLURM_ARRAY_TASK_ID=task))
        self.assertEqual(sweep_main(["--collect", str(out)]), 0)
        collected = json.loads((out / "sweep.json").read_text())["summaries"]
        local, _ = run_sweep(EXP, 2, 2, self.tmp / "local_for_slurm")
        self.assertEqual([results(s) for s in collected], [results(s) for s in local])
        # A task that has not run yet is reported, not silently dropped.
        shutil.rmtree(out / "seed2")
        self.assertEqual(sweep_main(["--collect", str(out)]), 1)

    def test_a_worker_without_the_project_is_named(self):
        self.assertEqual(_worker_has_project(mp.ROOT, os.environ["DMPL_BUILD_DIR"]), "")
        missing = _worker_has_project("/nonexistent", "/nonexistent/build")
        self.assertIn("/nonexistent/configs", missing)
        self.assertIn("dmpl_oneprocess", missing)


if __name__ == "__main__":
    sys.exit(unittest.main())
