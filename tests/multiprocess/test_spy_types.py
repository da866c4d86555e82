"""`tools/dmpl spy` (lcm-spy under a virtual display) finds every dmpl type: it prints
"Found N LCM types" with N the number of .lcm files."""
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


if __name__ == "__main__":
    sys.exit(unittest.main())
