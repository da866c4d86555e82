"""`cmake --install` gives a prefix that works without the source tree: its executables, its
libraries and headers (a program built against them links and runs a core), its configs and
message definitions, and its `dmpl` wrapper, which runs a short gait as a full process set, from
another directory with nothing of the source or build tree on any path, and gets the same
summary as the one-process run from the build tree."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import mp
from dmpl_tools.run import run_experiment

BUILD = Path(os.environ["DMPL_BUILD_DIR"])
SHORT = ["task.angle=0.5"]
SAME_KEYS = ["status", "object_dropped", "rotation_total_rad", "final_orientation_error_rad",
             "max_position_drift_m", "contacts_lost", "regrasps", "sim_time_s"]

# A program of a lab's own, built against the installed headers and one installed library.
PROGRAM = r"""
#include <cstdio>
#include "sim_process/sim/sim_scheduler.h"
#include "dmpl/joint_cmd_t.hpp"

struct Loop : dmpl::SimLoop {
  int steps = 0;
  void PublishTick(int64_t) override {}
  void ApplyCommand(const dmpl::JointCommand&) override {}
  void ApplyControl(const dmpl::SimControl&) override {}
  bool StepTo(int64_t) override { return ++steps == 3; }
  void Paused(const dmpl::SimControl&) override {}
  void Resumed(const dmpl::SimControl&, double) override {}
  void Fault(const std::string&) override {}
  void Finished(const dmpl::SimControl*, bool) override { std::printf("finished at %d\n", steps); }
};

int main() {
  dmpl::joint_cmd_t message{};
  Loop loop;
  dmpl::SimScheduleParams p;
  dmpl::SimScheduler scheduler(p, &loop);
  scheduler.Begin(0);
  for (int k = 0; k < 3; ++k) {
    dmpl::JointCommand c;
    c.seq = k + message.seq;
    scheduler.OnCommand(c, 0);
  }
  return scheduler.finished() ? 0 : 1;
}
"""


class InstallTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.work = Path(tempfile.mkdtemp(prefix="dmpl_install_"))
        cls.prefix = cls.work / "prefix"
        done = subprocess.run(["cmake", "--install", str(BUILD), "--prefix", str(cls.prefix)],
                              capture_output=True, text=True)
        if done.returncode != 0:
            raise AssertionError("cmake --install failed:\n" + done.stdout + done.stderr)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.work, ignore_errors=True)

    def test_the_layout(self):
        p = self.prefix
        for node in ("dmpl_sim", "dmpl_noise", "dmpl_ik", "dmpl_controller", "dmpl_supervisor",
                     "dmpl_oneprocess", "dmpl_record", "dmpl_logcols", "dmpl"):
            self.assertTrue(os.access(p / "bin" / node, os.X_OK), node)
        self.assertTrue((p / "lib/libdmpl_runtime.a").is_file())
        self.assertTrue((p / "include/dmpl/components/runtime/node.h").is_file())
        self.assertTrue((p / "include/dmpl/dmpl/hand_sensors_t.hpp").is_file())
        self.assertFalse(list((p / "include/dmpl").rglob("test")), "test sources are not installed")
        data = p / "share/dmpl"
        self.assertTrue((data / "configs/hand/dmpl_hand.urdf").is_file())
        self.assertEqual(sorted(f.name for f in (data / "lcmtypes").glob("*.lcm")),
                         sorted(f.name for f in (Path(mp.ROOT) / "lcmtypes").glob("*.lcm")))
        self.assertTrue((data / "python/dmpl_channels.py").is_file())
        self.assertTrue((data / "tools/python/dmpl_tools/run.py").is_file())
        self.assertTrue((data / "java/dmpl_types.jar").is_file())

    def test_a_program_builds_against_the_installed_headers_and_library(self):
        source = self.work / "program.cc"
        source.write_text(PROGRAM)
        exe = self.work / "program"
        lcm_flags = subprocess.run(["pkg-config", "--cflags", "lcm"], capture_output=True,
                                   text=True, check=True).stdout.split()
        subprocess.run(["c++", "-std=c++17", "-o", str(exe), str(source),
                        f"-I{self.prefix}/include/dmpl", *lcm_flags,
                        f"-L{self.prefix}/lib", "-ldmpl_sim_scheduler"], check=True)
        ran = subprocess.run([str(exe)], capture_output=True, text=True)
        self.assertEqual(ran.returncode, 0, ran.stdout + ran.stderr)
        self.assertEqual(ran.stdout.strip(), "finished at 3")

    def test_the_wrapper_runs_a_process_set_as_the_build_tree_does(self):
        config = "configs/experiments/fig10_gait_sphere.yaml"
        here, _ = run_experiment(str(Path(mp.ROOT) / config), out_dir=str(self.work / "here"),
                              seed=3, sets=SHORT, one_process=True, echo=False,
                              record="none")
        # Nothing of the source or build tree on any path: only the prefix.
        env = {k: v for k, v in os.environ.items()
               if k not in ("PYTHONPATH", "DMPL_ROOT", "DMPL_BUILD_DIR", "DMPL_OUT")}
        env["PATH"] = os.pathsep.join(d for d in env["PATH"].split(os.pathsep)
                                      if not d.startswith(str(BUILD)))
        env["DMPL_PYTHON"] = sys.executable
        elsewhere = self.work / "elsewhere"
        elsewhere.mkdir()
        args = [str(self.prefix / "bin/dmpl"), "run", str(self.prefix / "share/dmpl" / config),
                "--seed", "3", "--record", "none", "--quiet"]
        for s in SHORT:
            args += ["--set", s]
        done = subprocess.run(args, cwd=elsewhere, env=env, capture_output=True, text=True,
                              timeout=300)
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        runs = list((elsewhere / "out/runs").iterdir())  # the default --out: ./out
        self.assertEqual(len(runs), 1)
        there = json.loads((runs[0] / "summary.json").read_text())
        self.assertEqual(there["status"], "success", there)
        self.assertGreater(there["rotation_total_rad"], 0.4)
        for key in SAME_KEYS:
            self.assertEqual(there[key], here[key], key)


if __name__ == "__main__":
    sys.exit(unittest.main())
