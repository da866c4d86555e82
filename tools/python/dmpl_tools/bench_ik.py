"""tools/dmpl bench ik: median and p99 of one four-finger IK solve (ik_solve_us_median)."""
import json
import subprocess

from .paths import executable


def bench_ik(solves=20000):
    out = subprocess.run([executable("dmpl_bench_ik"), "--percentiles", str(solves)],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)
