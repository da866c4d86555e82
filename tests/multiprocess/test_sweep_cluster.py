"""Issue 19: sweeps on an existing distributed engine. A sweep's trials submitted to a Dask
scheduler (a scheduler and two workers started as separate processes on loopback, as
docs/clusters.md starts them: the scheduler without the project's paths) give the results of the
same sweep run here, also when a worker dies mid-sweep; an interrupted sweep resumes, running
only the trials it had not finished; a worker that cannot import the project stops the sweep
before any trial, with one error naming it; a Slurm array job's trials, collected, give the
results too."""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from pathlib import Path

import mp
from distributed import Client
from dmpl_tools.sweep import _worker_command, _worker_problem, run_sweep, worker_facts
from dmpl_tools.sweep import main as sweep_main

EXP = mp.ROOT + "/configs/experiments/fig8_sphere.yaml"
BUILD = os.environ["DMPL_BUILD_DIR"]
# What differs between two runs of one trial: the machine's time, and whether it was resumed.
NOT_RESULTS = {"wall_time_s", "realtime_factor", "resumed"}
# docs/clusters.md's environments: the scheduler's has none of the project's paths; the
# workers' has them on PYTHONPATH.
PLAIN = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
WITH_PATHS = dict(PLAIN, PYTHONPATH=f"{BUILD}/python:{mp.ROOT}/tools/python")


def results(summary):
    return {k: v for k, v in summary.items() if k not in NOT_RESULTS}


def sweep_results(out):
    """A sweep's sweep.json, but for what differs between two runs of a trial."""
    doc = json.loads((Path(out) / "sweep.json").read_text())
    doc["summaries"] = [results(s) for s in doc["summaries"]]
    return doc


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class SweepClusterTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = Path(tempfile.mkdtemp(prefix="dmpl_cluster_"))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def setUp(self):
        self.dask = []

    def start(self, env, *args):
        """`dask ARGS` (the venv's), each in its own process group: a nanny, its worker and
        the worker's trials die together."""
        log = open(self.tmp / f"dask-{self.id().split('.')[-1]}-{len(self.dask)}.log", "w")
        proc = subprocess.Popen([str(Path(sys.executable).parent / "dask"), *args], env=env,
                                stdout=log, stderr=subprocess.STDOUT, cwd=mp.ROOT,
                                start_new_session=True)
        self.dask.append((proc, log))
        return proc

    def cluster(self, *worker_envs):
        """A scheduler and one worker per environment, started as docs/clusters.md says (ports
        picked free); returns its address, once every worker is connected, and the workers."""
        port = free_port()
        address = f"tcp://127.0.0.1:{port}"
        self.start(PLAIN, "scheduler", "--host", "127.0.0.1", "--port", str(port))
        workers = [self.start(env, "worker", address, "--nworkers", "1", "--nthreads", "1")
                   for env in worker_envs]
        with Client(address, timeout=60) as client:
            client.wait_for_workers(len(workers), timeout=60)
        return address, workers

    def tearDown(self):
        for proc, log in self.dask:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            log.close()

    def test_a_cluster_sweep_gives_the_local_results_survives_a_worker_and_resumes(self):
        address, workers = self.cluster(WITH_PATHS, WITH_PATHS)
        local, local_rate = run_sweep(EXP, 4, 2, self.tmp / "local")
        # Kill a worker (its nanny too: it stays dead) once the first trial is done: its trial
        # runs again on the other.
        out, swept = self.tmp / "cluster", threading.Event()

        def kill_after_first():
            while not swept.is_set() and not list(out.glob("seed*/summary.json")):
                time.sleep(0.05)
            if not swept.is_set():
                os.killpg(workers[0].pid, signal.SIGKILL)
        killer = threading.Thread(target=kill_after_first)
        killer.start()
        try:
            clustered, rate = run_sweep(EXP, 4, 2, out, cluster=address)
        finally:
            swept.set()
            killer.join()
        self.assertIsNotNone(workers[0].poll(), "the worker was not killed mid-sweep")
        self.assertEqual(rate, local_rate)
        self.assertEqual([results(s) for s in clustered], [results(s) for s in local])
        self.assertEqual(sweep_results(out), sweep_results(self.tmp / "local"))
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

    def test_a_worker_without_the_projects_python_path_stops_the_sweep_at_submission(self):
        address, _ = self.cluster(WITH_PATHS, PLAIN)
        with Client(address, timeout=60) as client:
            has_paths = client.run(lambda: "PYTHONPATH" in os.environ)
        bad = [w for w, has in has_paths.items() if not has]
        self.assertEqual(len(bad), 1)
        out = self.tmp / "refused"
        cli = subprocess.run([sys.executable, "-m", "dmpl_tools.sweep", EXP, "--seeds", "2",
                              "--cluster", address, "--out", str(out)],
                             capture_output=True, text=True, cwd=mp.ROOT, timeout=120)
        self.assertEqual(cli.returncode, 2, cli.stderr)
        self.assertNotIn("Traceback", cli.stderr)
        self.assertEqual(cli.stderr.count("dmpl sweep: error:"), 1, cli.stderr)
        self.assertIn("1 of 2 workers cannot run the trials", cli.stderr)
        self.assertIn(f"{bad[0]}: ", cli.stderr)
        self.assertIn("No module named 'dmpl_tools'", cli.stderr)
        self.assertIn(f"PYTHONPATH={BUILD}/python:{mp.ROOT}/tools/python", cli.stderr)
        self.assertEqual(list(out.glob("seed*")), [], "a trial ran before the check")

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

    def test_a_worker_without_the_build_is_named(self):
        # The check a worker runs, in a worker's environment that points at another build.
        here = worker_facts()
        self.assertEqual(here["missing"], [])
        check = subprocess.run(_worker_command("--worker-facts"), capture_output=True, text=True,
                               env=dict(os.environ, DMPL_BUILD_DIR="/nonexistent/build"))
        problem = _worker_problem(check, here)
        self.assertIn("lacks /nonexistent/build/bin/dmpl_oneprocess", problem)
        self.assertIn(f"build /nonexistent/build (here {os.path.realpath(BUILD)})", problem)
        same = subprocess.run(_worker_command("--worker-facts"), capture_output=True, text=True)
        self.assertEqual(_worker_problem(same, here), "")


if __name__ == "__main__":
    sys.exit(unittest.main())
