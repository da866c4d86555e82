"""Every C++ executable parses its command line the same way (components/runtime/command_line.h):
--help exits 0 and lists every flag, each with a description; a bad value or an unknown flag is
one line on stderr that names the flag, exit 2; --key=value works like --key value."""
import os
import subprocess
import unittest

import mp

BIN = os.path.join(os.environ["DMPL_BUILD_DIR"], "bin")
CONFIG = os.path.join(mp.ROOT, "configs/experiments/static_grasp.yaml")
NODE_FLAGS = ["--config", "--params", "--set", "--lcm-url", "--name", "--print-config", "--check"]

# executable: (the flags its help lists, what it requires, a bad value and the flag its error
# names). What it requires is given with an unknown flag: CLI11 names a missing one first.
EXECUTABLES = {
    "dmpl_sim": (NODE_FLAGS, [], ["--config"], "--config"),
    "dmpl_noise": (NODE_FLAGS, [], ["--print-config=maybe"], "--print-config"),
    "dmpl_ik": (NODE_FLAGS, [], ["--lcm-url"], "--lcm-url"),
    "dmpl_controller": (NODE_FLAGS, [], ["--set"], "--set"),
    "dmpl_joint_player": (NODE_FLAGS, [], ["--check=perhaps"], "--check"),
    "dmpl_supervisor": (NODE_FLAGS + ["--dot", "--mermaid"], [], ["--mermaid=sometimes"],
                        "--mermaid"),
    "dmpl_config": (["--config", "--params", "--set"], ["--config", CONFIG], ["--set"], "--set"),
    "dmpl_oneprocess": (["--config", "--params", "--set", "--record", "--record-policy",
                         "--columns", "--columns-fields"], [], ["--record-policy"],
                        "--record-policy"),
    "dmpl_record": (["--lcm-url", "--channels", "--single-bus", "--policy", "--columns", "--fields",
                     "--run-id"], [], ["--run-id", "12x", "out.lcmlog"], "--run-id"),
    "dmpl_logcols": (["LOG", "DIR", "--channels", "--fields"], ["run.lcmlog", "columns"],
                     ["--channels"], "--channels"),
    "dmpl_calibrate": (["LOG", "--out", "--report", "--config"], ["run.lcmlog"], ["--out"],
                       "--out"),
    "dmpl_hand_geometry": (["--config"], [], ["--config"], "--config"),
    "dmpl_surface": (["LOG", "--directions"], ["run.lcmlog"], ["--directions", "0"],
                     "--directions"),
    "dmpl_link_clearance": (["LOG", "--config", "--every"], ["run.lcmlog", "--config", CONFIG],
                            ["--every", "0"], "--every"),
    "dmpl_bench_sim": (["--config", "--engine", "--warmup", "--steps"], [], ["--steps", "x"], "--steps"),
    "dmpl_bench_ik": (["--percentiles"], [], ["--percentiles=0"], "--percentiles"),
    "dmpl_bench_lcm_hop": (["echo", "ping"], ["ping"], ["ping", "--bytes", "many"], "--bytes"),
    "dmpl_channels_py": ([], [], ["--channels"], "--channels"),
}


def run(exe, *args):
    return subprocess.run([os.path.join(BIN, exe), *args], capture_output=True, text=True,
                          timeout=60)


def help_entries(text):
    """{flag, positional or subcommand: its description} from CLI11's help, where a description
    starts at column 30 (on the next line when the name is longer)."""
    entries, lines = {}, text.splitlines() + [""]
    for line, after in zip(lines, lines[1:]):
        if line.startswith("  ") and not line.startswith(" " * 30):
            name = line.split()[0].split(",")[-1]
            entries[name] = after.strip() if after.startswith(" " * 30) else line[30:].strip()
    return entries


class CommandLinesTest(unittest.TestCase):
    def assert_refused(self, exe, args, flag):
        r = run(exe, *args)
        self.assertEqual(r.returncode, 2, f"{exe} {args}: {r.stderr}")
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, f"{exe} {args}: {r.stderr}")
        self.assertIn(flag, lines[0], f"{exe} {args}")
        # `tools/dmpl calibrate` runs dmpl_calibrate, which says "dmpl calibrate:".
        self.assertRegex(lines[0], "^" + exe.replace("_", "[_ ]", 1) + ":")

    def test_help_lists_every_flag(self):
        for exe, (flags, _, _, _) in EXECUTABLES.items():
            with self.subTest(exe=exe):
                r = run(exe, "--help")
                self.assertEqual(r.returncode, 0, r.stderr)
                listed = help_entries(r.stdout)
                for flag in flags:
                    self.assertIn(flag, listed, f"{exe} --help:\n{r.stdout}")
                for name, description in listed.items():
                    self.assertTrue(description, f"{exe} --help: {name} has no description")

    def test_a_bad_value_is_one_line_and_exit_2(self):
        for exe, (_, _, bad, flag) in EXECUTABLES.items():
            with self.subTest(exe=exe):
                self.assert_refused(exe, bad, flag)

    def test_an_unknown_flag_is_one_line_and_exit_2(self):
        for exe, (_, required, _, _) in EXECUTABLES.items():
            with self.subTest(exe=exe):
                self.assert_refused(exe, required + ["--no-such-flag"], "--no-such-flag")

    def test_key_equals_value(self):
        r = run("dmpl_config", f"--config={CONFIG}", "--set=run.seed=7")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("seed: 7", r.stdout)
        r = run("dmpl_noise", f"--config={CONFIG}", "--set", "run.seed=7", "--check")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("configuration OK", r.stdout)
        self.assert_refused("dmpl_bench_sim", ["--steps=0"], "--steps")


if __name__ == "__main__":
    unittest.main()
