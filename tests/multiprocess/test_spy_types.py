"""`tools/dmpl spy` (lcm-spy under a virtual display) finds every dmpl type: it prints
"Found N LCM types" with N the number of .lcm files. `--bus NAME` watches the port of the bus
the build's channel table names (base port + 1000 × its index)."""
import glob
import os
import re
import signal
import subprocess
import sys
import time
import unittest

import mp


class SpyTest(unittest.TestCase):
    def test_finds_every_type(self):
        want = len(glob.glob(os.path.join(mp.ROOT, "lcmtypes", "*.lcm")))
        build = os.environ["DMPL_BUILD_DIR"]
        env = dict(os.environ)
        env.pop("DISPLAY", None)
        proc = subprocess.Popen([os.path.join(mp.ROOT, "tools/spy.sh"), build],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                env=env, start_new_session=True)
        found, lines = None, []
        deadline = time.monotonic() + 40
        try:
            for line in proc.stdout:
                lines.append(line)
                m = re.search(r"Found (\d+) LCM types", line)
                if m:
                    found = int(m.group(1))
                    break
                if time.monotonic() > deadline:
                    break
        finally:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        self.assertEqual(found, want, "".join(lines))


    def test_a_bus_is_watched_on_its_port_from_the_builds_table(self):
        from dmpl_channels import BUS_NAMES
        spy = [os.path.join(mp.ROOT, "tools/spy.sh"), os.environ["DMPL_BUILD_DIR"]]
        env = dict(os.environ, LCM_DEFAULT_URL="udpm://239.255.76.67:7667?ttl=0")
        env.pop("DISPLAY", None)
        bad = subprocess.run(spy + ["--bus", "nonsense"], capture_output=True, text=True, env=env)
        self.assertEqual(bad.returncode, 2)
        self.assertIn(" ".join(BUS_NAMES), bad.stderr)
        for name in ("targets", "monitor"):
            proc = subprocess.Popen(spy + ["--bus", name], stdout=subprocess.PIPE,
                                    stderr=subprocess.STDOUT, text=True, env=env,
                                    start_new_session=True)
            try:
                said = proc.stdout.readline()
            finally:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
            port = 7667 + 1000 * BUS_NAMES.index(name)
            self.assertIn(f"the {name} bus, udpm://239.255.76.67:{port}?ttl=0", said)

    def test_spy_python_and_cpp_share_one_url_rule(self):
        # components/runtime/lcm_url.h: a URL without a port has LCM's 7667 (C++ once appended
        # the port after the options, spy and Python left the URL alone: three rules).
        from dmpl_channels import BUS_NAMES
        from dmpl_tools.channels import bus_url
        self.assertEqual(bus_url("udpm://239.255.76.67?ttl=1", 1), "udpm://239.255.76.67:8667?ttl=1")
        self.assertEqual(bus_url("udpm://239.255.76.67:7700?ttl=0&recv_buf_size=9", 2),
                         "udpm://239.255.76.67:9700?ttl=0&recv_buf_size=9")
        self.assertEqual(bus_url("memq://", 1), "memq://")
        with self.assertRaisesRegex(ValueError, "port must be a number"):
            bus_url("udpm://239.255.76.67:x?ttl=0", 1)
        spy = [os.path.join(mp.ROOT, "tools/spy.sh"), os.environ["DMPL_BUILD_DIR"], "--bus",
               BUS_NAMES[1]]
        env = dict(os.environ, LCM_DEFAULT_URL="udpm://239.255.76.67?ttl=0")
        env.pop("DISPLAY", None)
        proc = subprocess.Popen(spy, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                env=env, start_new_session=True)
        try:
            said = proc.stdout.readline()
        finally:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        self.assertIn(f"the {BUS_NAMES[1]} bus, udpm://239.255.76.67:8667?ttl=0", said)
        bad = subprocess.run(spy, capture_output=True, text=True,
                             env=dict(env, LCM_DEFAULT_URL="udpm://239.255.76.67:x"))
        self.assertEqual(bad.returncode, 2)
        self.assertIn("port must be a number", bad.stderr)
        self.assertNotIn("Traceback", bad.stderr)


if __name__ == "__main__":
    sys.exit(unittest.main())
