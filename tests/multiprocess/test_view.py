"""Issue 16: the 3-D viewer. The hand it draws is the hand the controller computes (forward
kinematics from the URDF against the C++ kinematics' tip positions), the HTML replay of a log is
one self-contained page, and the live view listens to a running set without changing what the set
does (a lockstep run gives the same summary with and without it)."""
import json
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import unittest
from pathlib import Path

import numpy as np

import mp
from devtools import Browser
from dmpl_tools import channels, view
from dmpl_tools.hand_geometry import load_hand
from dmpl_tools.logdata import Columns, extract
from dmpl_tools.run import run_experiment

EXP = mp.ROOT + "/configs/experiments/"


# Run in the replay page: once the scene and the animation are loaded, the number of link nodes
# and the object's drawn position at t = 0 and at t = T1 of the timeline, into <pre id=...>.
PROBE = """<script>
const timer = setInterval(function() {
  const hand = viewer.scene_tree.find(["meshcat", "dmpl", "hand"]);
  if (Object.keys(hand.children).length == 0 || viewer.animator.actions.length == 0) return;
  clearInterval(timer);
  let out;
  try {
    const obj = viewer.scene_tree.find(["meshcat", "dmpl", "object", "true"]).object;
    const at = function(t) {
      const a = viewer.animator;
      a.play(); a.mixer.setTime(t); a.pause();
      obj.updateWorldMatrix(true, false);
      const p = new MeshCat.THREE.Vector3();
      obj.getWorldPosition(p);
      return [p.x, p.y, p.z];
    };
    out = {links: Object.keys(hand.children).length, p0: at(0.0), p1: at(T1)};
  } catch (e) { out = {error: String(e)}; }
  const pre = document.createElement("pre");
  pre.id = "dmpl-probe";
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
}, 200);
</script></body>"""


# Read in the live page: its clock (x: the sim time of the frame being drawn, y: of the last one
# drawn completely) and the object's pose as drawn (Meshcat decomposes each transform it receives
# into these).
LIVE_PROBE = """(function() {
  if (!("clock" in viewer.scene_tree.find(["meshcat", "dmpl"]).children)) return null;
  const node = (p) => viewer.scene_tree.find(["meshcat", "dmpl"].concat(p)).object;
  const o = node(["object", "true_axes"]), clock = node(["clock"]).position;
  return {t: clock.x, done: clock.y, p: [o.position.x, o.position.y, o.position.z],
          q: [o.quaternion.w, o.quaternion.x, o.quaternion.y, o.quaternion.z]};
})()"""


class ViewTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.out = Path(tempfile.mkdtemp(prefix="dmpl_view_"))
        cls.summary, _ = run_experiment(EXP + "fig10_gait_sphere.yaml", cls.out, echo=False,
                                        sets=["task.angle=0.2"], one_process=True,
                                        record="full")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.out, ignore_errors=True)

    def test_the_hand_drawn_is_the_hand_the_controller_computes(self):
        hand = load_hand(self.out / "config.yaml")
        with tempfile.TemporaryDirectory() as tmp:
            extract(self.out / "run.lcmlog", tmp,
                    {channels.SENSORS_TRUE: ["seq", "joint_position"],
                     channels.CONTROLLER_STATUS: ["seq", "tip_position"]})
            cols = Columns(tmp)
            truth, ctl = cols.table(channels.SENSORS_TRUE), cols.table(channels.CONTROLLER_STATUS)
            joints = cols.channels[channels.SENSORS_TRUE]["joints"]
            fingers = cols.channels[channels.CONTROLLER_STATUS]["fingers"]
        # The controller's tips of tick k come from the joints sensed at k (no joint noise here).
        index = {s: i for i, s in enumerate(truth["seq"])}
        checked = 0
        for j in range(0, len(ctl["seq"]), 97):
            i = index.get(ctl["seq"][j])
            if i is None:
                continue
            poses = hand.link_poses(dict(zip(joints, truth["joint_position"][i])))
            for k, f in enumerate(fingers):
                np.testing.assert_allclose(poses[f + "_tip"][:3, 3], ctl["tip_position"][j][k],
                                           atol=1e-6, err_msg=f"finger {f} at seq {ctl['seq'][j]}")
            checked += 1
        self.assertGreater(checked, 10)

    def test_the_replay_is_one_page_that_needs_nothing_else(self):
        page = self.out / "replay.html"
        view.write_replay(self.out / "run.lcmlog", page)
        text = page.read_text()
        self.assertIsNone(re.search(r"<script[^>]+src=", text), "a script it would fetch")
        self.assertIsNone(re.search(r"<link[^>]+href=", text), "a style sheet it would fetch")
        self.assertIn("dmpl-overlay", text)
        self.assertIn("MeshCat.Viewer", text)
        # 30 frames a second of the run, each with a text for the overlay.
        texts = re.search(r"const texts = (\[.*?\]);", text).group(1)
        n = texts.count('"t = ')
        self.assertAlmostEqual(n / 30.0, self.summary["sim_time_s"], delta=0.1)
        self.assertIn("Tasks", texts)

    def test_the_replay_in_a_browser_draws_the_hand_and_moves_the_object(self):
        # Headless Chromium (installed by tools/dmpl) opens the replay, waits until the scene is
        # built, reads the scene graph and the object's drawn position at two times of the
        # timeline, and takes a screenshot.
        chromium = shutil.which("chromium")
        self.assertIsNotNone(chromium, "chromium is missing: tools/dmpl setup installs it")
        page = self.out / "replay.html"
        view.write_replay(self.out / "run.lcmlog", page)
        t1 = 2.0
        probe = PROBE.replace("T1", str(t1))
        (self.out / "probe.html").write_text(page.read_text().replace("</body>", probe, 1))
        browser = [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--use-gl=swiftshader",
                   "--enable-unsafe-swiftshader", "--virtual-time-budget=10000"]
        r = subprocess.run(browser + ["--dump-dom", (self.out / "probe.html").as_uri()],
                           capture_output=True, text=True, timeout=120)
        found = re.search(r'<pre id="dmpl-probe">(.*?)</pre>', r.stdout)
        self.assertIsNotNone(found, r.stderr[-2000:])
        drawn = json.loads(found.group(1))
        self.assertNotIn("error", drawn)
        hand = load_hand(self.out / "config.yaml")
        self.assertEqual(drawn["links"], len([k for k, v in hand.shapes.items() if v]))
        # The drawn object is where the truth was (the palm sits at the origin, so distances
        # from it and between two times are the palm frame's; Meshcat's y is the world's up,
        # the palm's x), within the replay's rounding (10 um).
        with tempfile.TemporaryDirectory() as tmp:
            extract(self.out / "run.lcmlog", tmp, {channels.SENSORS_TRUE: ["utime",
                                                                           "object_position"]})
            truth = Columns(tmp).table(channels.SENSORS_TRUE)
        t = (truth["utime"] - truth["utime"][0]) * 1e-6
        at = [truth["object_position"][int(np.argmin(abs(t - x)))] for x in (0.0, t1)]
        p0, p1 = np.array(drawn["p0"]), np.array(drawn["p1"])
        self.assertAlmostEqual(np.linalg.norm(p0), np.linalg.norm(at[0]), delta=1e-4)
        self.assertAlmostEqual(p0[1], at[0][0], delta=1e-4)
        moved = np.linalg.norm(at[1] - at[0])
        self.assertGreater(moved, 1e-4)
        self.assertAlmostEqual(np.linalg.norm(p1 - p0), moved, delta=2e-4)
        # A screenshot: the palm (light grey) fills the lower middle, over the blue background.
        png = self.out / "replay.png"
        subprocess.run(browser + ["--window-size=1000,700", f"--screenshot={png}",
                                  page.as_uri()], capture_output=True, timeout=120)
        import matplotlib.image
        image = matplotlib.image.imread(png)[..., :3]
        middle = image[380:460, 450:600]
        grey = (np.abs(middle[..., 0] - middle[..., 2]) < 0.08) & (middle.mean(axis=2) > 0.6)
        self.assertGreater(grey.mean(), 0.3, "no palm where the camera looks")

    def test_a_log_without_the_truth_is_refused_naming_the_channel(self):
        import lcm
        path = self.out / "no_truth.lcmlog"
        log = lcm.EventLog(str(path), "w", overwrite=True)
        log.write_event(0, channels.HEARTBEAT, b"\x00" * 40)
        log.close()
        with self.assertRaises(view.ViewError) as e:
            view.write_replay(path, self.out / "no_truth.html")
        self.assertIn(channels.SENSORS_TRUE, str(e.exception))
        self.assertFalse((self.out / "no_truth.html").exists())

    def test_a_truncated_log_replays_up_to_its_last_complete_event(self):
        full = (self.out / "run.lcmlog").read_bytes()
        cut = self.out / "cut" / "run.lcmlog"
        cut.parent.mkdir(exist_ok=True)
        cut.write_bytes(full[: len(full) // 2 + 7])  # mid-event
        shutil.copy(self.out / "config.yaml", cut.parent / "config.yaml")
        frames, *_ = view.read_frames(cut, 30.0)
        whole, *_ = view.read_frames(self.out / "run.lcmlog", 30.0)
        self.assertGreater(len(frames), 10)
        self.assertLess(len(frames), len(whole))
        # Every frame carries the simulator's force on the fingers' links (the link-touch
        # marker's), read from the log, not left unknown.
        for frame in whole:
            self.assertTrue(np.isfinite(frame["link_force"]).all(), frame["t"])
            # ... and the palm's gravity (palm up here: along palm -x), which turns the hand.
            np.testing.assert_allclose(frame["gravity"], [-9.81, 0.0, 0.0], atol=1e-9)

    def test_the_palm_is_drawn_turned_as_its_gravity_turned(self):
        # Palm up (gravity palm -x) turned 90 deg about palm y (gravity palm -z): the least
        # rotation taking the gravity now back to the first is that turn, as the simulator's
        # sim.palm_motion makes it (test: hand_sim_test, ATurningPalmTurnsGravity...).
        turn = view.rotation_between([0.0, 0.0, -9.81], [-9.81, 0.0, 0.0])
        np.testing.assert_allclose(turn, [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], atol=1e-12)
        rng = np.random.default_rng(1)
        for _ in range(100):
            a, b = rng.normal(size=3), rng.normal(size=3)
            r = view.rotation_between(a, b)
            np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
            np.testing.assert_allclose(r @ (a / np.linalg.norm(a)), b / np.linalg.norm(b),
                                       atol=1e-12)
        np.testing.assert_allclose(view.rotation_between([0, 0, 1], [0, 0, -1]) @ [0, 0, 1],
                                   [0, 0, -1], atol=1e-12)

    def test_bad_input_is_one_clear_error(self):
        for args, message in ((["/no/such.lcmlog"], "no such log"),
                              ([str(self.out / "config.yaml"), "--html", "/tmp/x.html"],
                               "dmpl view:"),
                              (["--fps", "0"], "--fps")):
            r = subprocess.run([sys.executable, "-m", "dmpl_tools.view", *args], cwd=mp.ROOT,
                               capture_output=True, text=True, timeout=60)
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertIn(message, r.stderr)
            self.assertNotIn("Traceback", r.stderr)

    def test_the_live_view_listens_without_changing_the_run(self):
        config = view.experiment.resolve(EXP + "fig8_sphere.yaml")
        stats = {}
        viewer = threading.Thread(target=lambda: stats.update(
            view.view_live(mp.URL, config, fps=30, duration_s=25)), daemon=True)
        viewer.start()
        time.sleep(2)
        with_view, _ = run_experiment(EXP + "fig8_sphere.yaml", tempfile.mkdtemp(), echo=False,
                                      record="none")
        viewer.join(timeout=40)
        without, _ = run_experiment(EXP + "fig8_sphere.yaml", tempfile.mkdtemp(), echo=False,
                                    record="none")
        self.assertGreater(stats.get("frames", 0), 30)
        for key in ("status", "rotation_total_rad", "final_orientation_error_rad",
                    "max_position_drift_m", "grip_force_total_n", "regrasps", "sim_time_s"):
            self.assertEqual(with_view[key], without[key], key)


class LiveBrowserTest(unittest.TestCase):
    def test_the_live_page_draws_the_truth_of_the_instant_it_shows(self):
        # `tools/dmpl view` (as a user starts it), headless Chromium on the URL it prints, and a
        # short lockstep run on the set's bus, recorded. While it runs, the page is sampled:
        # which instant it shows (the frame's stamp) and where it draws the object. The run
        # keeps one CPU (the viewer, the browser and the recorder share the other, as on a
        # user's machine with more CPUs than the loop needs).
        out = Path(tempfile.mkdtemp(prefix="dmpl_live_"))
        self.addCleanup(shutil.rmtree, out, ignore_errors=True)
        fps = 15.0
        viewer = subprocess.Popen(
            [sys.executable, "-m", "dmpl_tools.view", "--config", EXP + "fig10_gait_sphere.yaml",
             "--lcm-url", mp.URL, "--fps", str(fps), "--duration", "120"],
            cwd=mp.ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.addCleanup(lambda: (viewer.kill(), viewer.wait(), viewer.stdout.close()))
        url = None
        for line in viewer.stdout:
            found = re.search(r"view: open (\S+)", line)
            if found:
                url = found.group(1)
                break
        self.assertIsNotNone(url, "the viewer printed no URL")
        browser = Browser(url, idle=True)
        self.addCleanup(browser.close)
        browser.wait_for("typeof viewer != 'undefined' && Object.keys(viewer.scene_tree.find("
                         "['meshcat', 'dmpl', 'hand']).children).length > 0", 60,
                         "the live page to build the hand")
        # The truth as the viewer gets it (the simulator's copy for viewers, 30 Hz), every
        # message kept while the page is asked (LCM's queue holds 30 by default).
        from dmpl import hand_sensors_t
        truth = {}

        def keep(channel, data):
            m = hand_sensors_t.decode(data)
            truth[round(m.utime * 1e-6, 6)] = m.object
        bus = mp.Bus()
        bus.buses.subscribe(channels.VIEW_TRUTH, keep).set_queue_capacity(100000)
        result = {}
        run = threading.Thread(target=lambda: result.update(run_experiment(
            EXP + "fig10_gait_sphere.yaml", out, echo=False, sets=["task.angle=12.0"],
            record=False, cpus=[-1])[0]))
        run.start()
        samples = []
        while run.is_alive():
            bus.spin(0.1)
            drawn = browser.evaluate(LIVE_PROBE)
            if drawn and drawn["done"] >= 0:  # a frame has been drawn
                samples.append(drawn)
        run.join()
        bus.spin(0.2)
        self.assertEqual(result["exit_code"], 0, result.get("problems"))
        # The page receives frames: it showed several instants of the run.
        stamps = sorted({s["done"] for s in samples})
        self.assertGreaterEqual(len(stamps), 5, f"{len(samples)} samples")
        # The object drawn is the truth of the instant the page shows; a sample taken while a
        # frame arrives finds the pose of that frame or of the one before: within one frame.
        # The live view sends a pose when it moved by its resolution (10 um, 1e-5 in the
        # quaternion): the drawn pose is the truth's to that.
        for s in samples:
            missing = [x for x in {s["done"], s["t"]} if round(x, 6) not in truth]
            self.assertFalse(missing, f"no truth message at {missing} s: "
                             f"{sorted(truth)[:3]}..{sorted(truth)[-3:]} ({len(truth)})")
            shown = [truth[round(x, 6)] for x in {s["done"], s["t"]}]
            error = [np.linalg.norm(np.subtract(o.position, s["p"])) for o in shown]
            turn = [1.0 - abs(np.dot(o.orientation, s["q"])) for o in shown]
            self.assertTrue(any(e < 1e-5 and a < 1e-9 for e, a in zip(error, turn)),
                            f"drawn with the clock at {s['done']:.3f} s (drawing {s['t']:.3f}): "
                            f"{s['p']}; the truth then: {[o.position for o in shown]}")

if __name__ == "__main__":
    sys.exit(unittest.main())
