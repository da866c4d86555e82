"""Issue 19: sweeps on an existing distributed engine. A sweep's trials submitted to a Dask
scheduler (here a scheduler and two workers started as separate processes on loopback, as on a
lab's machines) give the results of the same sweep run here, also when a worker dies mid-sweep;
an interrupted sweep resumes, running only the trials it had not finished; a Slurm array job's
trials, collected, give them too."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
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

    def start(self, *args):
        """A Dask process (`dask scheduler` or `dask worker`), as the README starts them."""
        log = open(self.tmp / f"dask-{len(self.dask)}.log", "w")
        proc = subprocess.Popen([str(Path(sys.executable).parent / "dask"), *args],
                                stdout=log, stderr=subprocess.STDOUT, cwd=mp.ROOT)
        self.dask.append((proc, log))
        return proc

    def tearDown(self):
        for proc, log in getattr(self, "dask", []):
            if proc.poll() is None:
                proc.kill()
            proc.wait()
            log.close()

    def test_a_cluster_sweep_gives_the_local_results_survives_a_worker_and_resumes(self):
        # A scheduler and two workers, separate processes on loopback (no nanny: a killed
        # worker stays dead); one trial per worker at a time.
        self.dask = []
        file = self.tmp / "scheduler.json"
        self.start("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                   "--scheduler-file", str(file))
        end = time.monotonic() + 60
        while not file.exists() and time.monotonic() < end:
            time.sleep(0.1)
        address = json.loads(file.read_text())["address"]
        workers = [self.start("worker", address, "--nthreads", "1", "--no-nanny",
                              "--no-dashboard", "--name", f"w{i}") for i in range(2)]
        local, local_rate = run_sweep(EXP, 4, 2, self.tmp / "local")
        # Kill a worker once the first trial is done: its trial runs again on the other.
        out = self.tmp / "cluster"

        def kill_after_first():
            end = time.monotonic() + 120
            while time.monotonic() < end and not list(out.glob("seed*/summary.json")):
                time.sleep(0.05)
            workers[0].kill()
        killer = threading.Thread(target=kill_after_first)
        killer.start()
        clustered, rate = run_sweep(EXP, 4, 2, out, cluster=address)
        killer.join()
        self.assertIsNotNone(workers[0].poll(), "the worker was not killed mid-sweep")
        self.assertEqual(rate, local_rate)
        self.assertEqual([results(s) for s in clustered], [results(s) for s in local])
        self.assertEqual(json.loads((out / "sweep.json").read_text())["success_rate"],
                         json.loads((self.tmp / "local" / "sweep.json").read_text())
                         ["success_rate"])
        # Interrupted after two trials: the others' summaries are gone. --resume runs only
        # those two.
        for seed in (3, 4):
            (out / f"seed{seed}" / "summary.json").unlink()
        again, _ = run_sweep(EXP, 4, 2, out, cluster=address, resume=True)
        self.assertEqual([bool(s.get("resumed")) for s in again], [True, True, False, False])
        self.assertEqual([results(s) for s in again], [results(s) for s in local])
        # A trial of another config is not taken for a finished one.
        other, _ = run_sweep(EXP, 1, 1, out, resume=True, sets=["noise.object_position_sigma=0.001"])
        self.assertNotIn("resumed", other[0])

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
