"""A bad set file is rejected before anything starts; a failing process makes the launcher exit
non-zero; a process that ignores its stop signal is killed after stop_time_allowed."""
import os
import subprocess
import sys
import tempfile
import textwrap
import time
import unittest

import mp


def write_set(text):
    """A process set file in a new directory: (its path, the directory)."""
    d = tempfile.mkdtemp(prefix="dmpl_set_")
    path = os.path.join(d, "set.yaml")
    with open(path, "w") as f:
        f.write(textwrap.dedent(text))
    return path, d


def run_set(text, *extra, timeout=30):
    path, d = write_set(text)
    return subprocess.run([sys.executable, "-m", "dmpl_tools.launch", path, "--run-dir", d,
                           "--no-record", *extra], cwd=mp.ROOT, capture_output=True, text=True,
                          timeout=timeout), d


class LauncherErrorsTest(unittest.TestCase):
    def assert_rejected(self, text, message):
        r, d = run_set(text)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(message, r.stderr)
        self.assertEqual([f for f in os.listdir(d) if f.endswith(".log")], [],
                         "nothing may start for a bad set")

    def test_bad_sets(self):
        self.assert_rejected("name: x\nprocesses: []\n", "at least one process")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: sleep, colour: red}\n",
                             "unknown key 'colour'")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: no_such_program_dmpl}\n",
                             "'no_such_program_dmpl' not found")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: sleep}\n"
                             "  - {name: a, exec: sleep}\n", "duplicate process name 'a'")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: sleep, max_restarts: many}\n",
                             "'max_restarts' expects int")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: sleep, stop_signal: SIGFOO}\n",
                             "unknown stop_signal 'SIGFOO'")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: sleep, args: ['${nope}']}\n",
                             "unknown variable ${nope}")
        self.assert_rejected("name: [\n", "YAML syntax error")
        self.assert_rejected("name: x\ncpus: [4096]\nprocesses:\n  - {name: a, exec: sleep}\n",
                             "CPU 4096 is not available")
        self.assert_rejected("name: x\nprocesses:\n  - {name: a, exec: sleep, cpus: [one]}\n",
                             "expects CPU numbers")

    def test_cpus_pin_the_processes(self):
        # The set's cpus apply to every process that names none; -1 is the last CPU.
        last = sorted(os.sched_getaffinity(0))[-1]
        r, _ = run_set("""
            name: pinned
            cpus: [-1]
            processes:
              - {name: b, exec: sh, args: [-c, "grep Cpus_allowed_list /proc/self/status; sleep 5"],
                 cpus: [0]}
              - {name: a, exec: sh, args: [-c, "grep Cpus_allowed_list /proc/self/status; sleep 1"],
                 exit_ends_set: true}
            """)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout, rf"\[a\] Cpus_allowed_list:\s+{last}\n")
        self.assertRegex(r.stdout, r"\[b\] Cpus_allowed_list:\s+0\n")

    def test_processes_die_with_a_killed_launcher(self):
        # SIGKILL leaves the launcher no chance to stop its set: the kernel does it
        # (PR_SET_PDEATHSIG, set before the process's program starts).
        path, d = write_set("name: orphans\nprocesses:\n"
                            "  - {name: a, exec: sh, args: [-c, 'echo pid $$; sleep 60']}\n")
        launcher = subprocess.Popen([sys.executable, "-m", "dmpl_tools.launch", path, "--run-dir",
                                     d, "--no-record"], cwd=mp.ROOT, stdout=subprocess.PIPE,
                                    text=True)
        pid = None
        for line in launcher.stdout:
            if "pid " in line and line.startswith("[a]"):
                pid = int(line.split("pid ")[1])
                break
        self.assertIsNotNone(pid)
        launcher.kill()
        launcher.wait()

        def alive():  # a killed process waiting to be reaped counts as gone
            try:
                with open(f"/proc/{pid}/stat") as f:
                    return f.read().split(") ")[1][0] != "Z"
            except FileNotFoundError:
                return False
        deadline = time.monotonic() + 2.0
        while alive() and time.monotonic() < deadline:
            time.sleep(0.02)
        self.assertFalse(alive(), "the set's process outlived its launcher")

    def test_failing_process_fails_the_set(self):
        r, _ = run_set("""
            name: failing
            processes:
              - {name: ok, exec: sleep, args: ["30"]}
              - {name: bad, exec: sh, args: [-c, "echo doomed; exit 3"], exit_ends_set: true}
            """)
        self.assertEqual(r.returncode, 1)
        self.assertIn("[bad] doomed", r.stdout)

    def test_respawn_limit_then_failure(self):
        r, _ = run_set("""
            name: crashing
            processes:
              - {name: crash, exec: sh, args: [-c, "exit 1"], auto_respawn: true,
                 respawn_delay_s: 0.05, max_restarts: 2}
            """)
        self.assertEqual(r.returncode, 1)
        self.assertIn("respawn 2/2", r.stderr)
        self.assertIn("restart limit reached", r.stderr)

    def test_stubborn_process_is_killed_with_its_children(self):
        t0 = time.monotonic()
        r, d = run_set("""
            name: stubborn
            processes:
              - name: stubborn
                exec: sh
                args: [-c, "trap '' INT TERM; sleep 60 & echo child $!; wait"]
                stop_time_allowed: 0.5
            """, "--duration", "1")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("SIGKILL", r.stderr)
        self.assertLess(time.monotonic() - t0, 10)
        child = int(next(l for l in r.stdout.splitlines() if "child" in l).split()[-1])
        time.sleep(0.2)
        self.assertFalse(mp.pid_alive(child), "the process group was not killed")


if __name__ == "__main__":
    sys.exit(unittest.main())
