"""Issue 19: the loop across two hosts. Two network namespaces joined by a veth pair stand for
two machines: the simulator and the noise injector on one (`tools/dmpl run --only`, which also
records the run and writes its summary), the IK, the controller and the supervisor on the other,
started by hand from the run's sensing config as a user would. Multicast is routed on the link
and the URL says ttl=1: one hop, the link, nothing beyond. A short lockstep gait gives the summary
it gives on one host."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

import mp
from dmpl_tools.run import run_experiment

GAIT = mp.ROOT + "/configs/experiments/fig10_gait_sphere.yaml"
SETS = ["task.angle=1.0"]
URL = "udpm://239.255.76.67:7667?ttl=1"
BIN = Path(os.environ["DMPL_BUILD_DIR"]) / "bin"
NOT_RESULTS = {"wall_time_s", "realtime_factor"}


def sh(*cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)}: {r.stderr.strip()}")


class TwoHostsTest(unittest.TestCase):
    def setUp(self):
        if os.geteuid() != 0:
            self.skipTest("network namespaces need root (CI runs as root)")
        tag = f"dmpl{os.getpid() % 100000}"
        self.hosts = {"a": tag + "a", "b": tag + "b"}
        self.link_b = tag + "y"
        for ns in self.hosts.values():
            sh("ip", "netns", "add", ns)
            self.addCleanup(subprocess.run, ["ip", "netns", "delete", ns])
        sh("ip", "link", "add", tag + "x", "type", "veth", "peer", "name", tag + "y")
        for ns, dev, addr in ((self.hosts["a"], tag + "x", "10.213.0.1/24"),
                              (self.hosts["b"], tag + "y", "10.213.0.2/24")):
            sh("ip", "link", "set", dev, "netns", ns)
            on = ["ip", "netns", "exec", ns]
            sh(*on, "ip", "link", "set", "lo", "up")
            sh(*on, "ip", "addr", "add", addr, "dev", dev)
            sh(*on, "ip", "link", "set", dev, "up")
            sh(*on, "ip", "route", "add", "224.0.0.0/4", "dev", dev)
        self.tmp = Path(tempfile.mkdtemp(prefix="dmpl_two_hosts_"))
        self.addCleanup(subprocess.run, ["rm", "-rf", str(self.tmp)])

    def on(self, host, *cmd, **kwargs):
        return subprocess.Popen(["ip", "netns", "exec", self.hosts[host], *cmd], cwd=mp.ROOT,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                **kwargs)

    def test_the_loop_across_two_hosts_gives_the_one_host_summary(self):
        one, _ = run_experiment(GAIT, self.tmp / "one_host", echo=False, sets=SETS)
        out = self.tmp / "host_a"
        set_args = sum((["--set", s] for s in SETS), [])
        host_a = self.on("a", sys.executable, "-m", "dmpl_tools.run", GAIT, "--out", str(out),
                         "--only", "dmpl_sim,dmpl_noise", "--lcm-url", URL, "--quiet", *set_args)
        sensing = out / "config.sensing.yaml"
        end = time.monotonic() + 60
        while not sensing.exists() and time.monotonic() < end and host_a.poll() is None:
            time.sleep(0.1)
        self.assertTrue(sensing.exists(), host_a.stdout.read() if host_a.poll() is not None else "")
        host_b = [self.on("b", str(BIN / exe), "--config", str(sensing), "--lcm-url", URL)
                  for exe in ("dmpl_ik", "dmpl_controller", "dmpl_supervisor")]
        try:
            output, _ = host_a.communicate(timeout=180)
        finally:
            for p in host_b:
                p.send_signal(signal.SIGINT)
                p.communicate(timeout=30)
        two = json.loads((out / "summary.json").read_text())
        self.assertEqual(two["status"], "success", (two.get("problems"), output[-2000:]))
        self.assertEqual(mp.summary_differences(one, two, NOT_RESULTS), {})
        # The loop crossed the link: host B received at least the sensed data of every tick
        # from host A, and sent back at least a command for each.
        stats = json.loads(subprocess.run(
            ["ip", "netns", "exec", self.hosts["b"], "ip", "-j", "-s", "link", "show",
             self.link_b], capture_output=True, text=True, check=True).stdout)[0]["stats64"]
        ticks = two["sim_time_s"] / 0.001
        self.assertGreater(stats["rx"]["packets"], ticks)
        self.assertGreater(stats["tx"]["packets"], ticks)


if __name__ == "__main__":
    sys.exit(unittest.main())
