"""The golden-summary regression test: short one-process runs whose summaries must not change.

    tools/dmpl golden            # run every case of tests/golden/cases.yaml, compare
    tools/dmpl golden --update   # write the summaries as the new golden files (say why in the commit)

Each case's summary.json, less what depends on the machine's speed (wall time, real-time
factor), is compared field by field with tests/golden/CASE.json: exactly, bit for bit, on a
machine like the one that wrote them (tests/golden/machine.json: the CPU's model and the
instruction sets glibc's maths chooses its code by). On another CPU the last bits of sin or atan2
may differ and contacts amplify them, so there only the discrete outcome is compared (status, drop,
supervisor state, goals) and the largest float deviations are printed.
"""
import argparse
import concurrent.futures
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
VOLATILE = {"wall_time_s", "realtime_factor"}
DISCRETE = ["status", "object_dropped", "supervisor_state", "supervisor_finished",
            "supervisor_failed", "goals_reached"]


def machine():
    flags, model = set(), ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name") and not model:
                model = line.split(":", 1)[1].strip()
            if line.startswith("flags") and not flags:
                flags = set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return {"cpu": model, "arch": platform.machine(),
            "isa": sorted(flags & {"fma", "avx", "avx2", "avx512f", "sse4_2"})}


def written_on(machines, name):
    """The machine a case's golden file was written on: machine.json's, unless the case was
    written alone on another (its entry under `cases`)."""
    return machines.get("cases", {}).get(name) or {k: v for k, v in machines.items() if k != "cases"}


def write_machines(here, names, all_cases):
    """Records where the files were written. Updating only some cases on a machine other than
    the one the rest were written on keeps the rest's record and notes these cases' own."""
    path = HERE / "machine.json"
    machines = {} if all_cases or not path.is_file() else json.loads(path.read_text())
    per_case = machines.pop("cases", {})
    if not machines:
        machines, per_case = dict(here), {}
    for name in names:
        per_case.pop(name, None)
        if here != machines:
            per_case[name] = here
    if per_case:
        machines["cases"] = dict(sorted(per_case.items()))
    path.write_text(json.dumps(machines, indent=1) + "\n")


def run_case(case, out_dir):
    out = Path(out_dir) / case["name"]
    cmd = [sys.executable, "-m", "dmpl_tools.run", str(ROOT / case["config"]), "--one-process",
           "--quiet", "--record", "none", "--out", str(out), "--seed", str(case.get("seed", 1))]
    for key, value in (case.get("set") or {}).items():
        cmd += ["--set", f"{key}={json.dumps(value)}"]
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    summary_file = out / "summary.json"
    if not summary_file.is_file():  # reported as the case's failure, the others still run
        return {"error": f"no summary (exit {proc.returncode}): "
                         f"{(proc.stdout + proc.stderr)[-1500:]}"}
    summary = json.loads(summary_file.read_text())
    return {k: v for k, v in summary.items() if k not in VOLATILE}


def differences(golden, got, exact):
    keys = DISCRETE if not exact else sorted(set(golden) | set(got))
    diffs = [f"{k}: {golden.get(k, '<missing>')!r} -> {got.get(k, '<missing>')!r}"
             for k in keys if (k in golden or k in got) and golden.get(k) != got.get(k)]
    return diffs


def largest_float_deviation(golden, got):
    worst = (0.0, "")
    for k, v in golden.items():
        w = got.get(k)
        if isinstance(v, float) and isinstance(w, float):
            rel = abs(w - v) / max(abs(v), 1e-12)
            worst = max(worst, (rel, k))
    return worst


def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/dmpl golden", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--update", action="store_true", help="write the golden files")
    ap.add_argument("--only", help="comma-separated case names")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    cases = yaml.safe_load((HERE / "cases.yaml").read_text())["cases"]
    if args.only:
        wanted = set(args.only.split(","))
        unknown = wanted - {c["name"] for c in cases}
        if unknown:
            print(f"golden: no case named {', '.join(sorted(unknown))}", file=sys.stderr)
            return 2
        cases = [c for c in cases if c["name"] in wanted]
    with tempfile.TemporaryDirectory(prefix="dmpl-golden-") as tmp:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(args.jobs, 1)) as pool:
            results = list(pool.map(lambda c: run_case(c, tmp), cases))
    here = machine()
    if args.update:
        broken = [c["name"] for c, r in zip(cases, results) if "error" in r and "status" not in r]
        if broken:
            print(f"golden: not written: {', '.join(broken)} gave no summary", file=sys.stderr)
            return 1
        for case, summary in zip(cases, results):
            (HERE / f"{case['name']}.json").write_text(json.dumps(summary, indent=1, sort_keys=True) + "\n")
        write_machines(here, [c["name"] for c in cases], all_cases=not args.only)
        print(f"golden: wrote {len(cases)} summaries ({here['cpu']})")
        return 0
    machines = json.loads((HERE / "machine.json").read_text())
    others = [c["name"] for c in cases if written_on(machines, c["name"]) != here]
    if others:
        print(f"golden: {len(others)} of {len(cases)} cases were written on another machine than "
              f"this one ({here}; machine.json): for them the discrete outcome only is compared")
    failed = 0
    for case, got in zip(cases, results):
        exact = case["name"] not in others
        path = HERE / f"{case['name']}.json"
        if not path.is_file():
            print(f"FAIL {case['name']}: no golden file {path.relative_to(ROOT)} "
                  "(tools/dmpl golden --update writes it)")
            failed += 1
            continue
        golden = json.loads(path.read_text())
        diffs = differences(golden, got, exact)
        if diffs:
            failed += 1
            print(f"FAIL {case['name']}:\n  " + "\n  ".join(diffs))
        else:
            rel, key = largest_float_deviation(golden, got)
            note = "" if exact else f" (largest float deviation {rel:.2g} in {key or '-'})"
            print(f"same {case['name']}{note}")
    print(f"golden: {len(cases) - failed} of {len(cases)} cases unchanged")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
