#include <gtest/gtest.h>

#include <cmath>

#include "supervisor/supervisor.h"

namespace dmpl {
namespace {

const std::vector<std::string> kFingers = {"T", "F", "M", "R"};

TaskFile Load(const std::string& name) {
  return LoadTaskFile(std::string(DMPL_SOURCE_DIR) + "/configs/tasks/" + name + ".yaml", kFingers);
}

// Drives a Supervisor with scripted controller views.
struct Driver {
  explicit Driver(const std::string& task_file, TaskParams tp = {}, SupervisorParams sp = {})
      : Driver(Load(task_file), tp, sp) {}
  Driver(TaskFile tasks, TaskParams tp, SupervisorParams sp = {})
      : sup(kFingers, std::move(tasks), tp, sp) {
    view.fingers.resize(4);
    view.object.translation() = Eigen::Vector3d(0.07, 0.0, 0.015);
  }
  const SupervisorOutput& Tick(double dt = 0.01) {
    view.time_s += dt;
    ++view.seq;
    const SupervisorOutput& out = sup.Step(view);
    view.events.clear();
    view.motion_done = false;
    return out;
  }
  void Touch(bool all = true) {
    for (auto& f : view.fingers) f.in_contact = all;
  }
  void Event(EventType type, int finger = -1) { view.events.push_back({type, finger, 0.0, ""}); }
  // Runs the grasp of Fig. 5 to the start of the first task.
  void Grasp() {
    Tick();
    Touch();
    Tick();
    view.grasp_stable = true;
    for (int i = 0; i < 100 && !sup.regrasp().is(RegraspState::S1); ++i) Tick();
    for (int i = 0; i < 100 && sup.grasp_state() != GraspState::Tasks; ++i) Tick();
  }
  Supervisor sup;
  ControllerView view;
};

TEST(SupervisorTest, GraspChartFromHeldObjectToTasksToDone) {
  Driver d("fig8_rotate");
  EXPECT_EQ(d.sup.grasp_state(), GraspState::ObjectHeld);
  const SupervisorOutput& out = d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Approaching);
  for (const auto& f : out.task.fingers) EXPECT_EQ(f.primitive, Primitive::kPosition);
  // Three fingers touch: they switch to composite; the fourth reaches its point untouched and is
  // sent further in.
  for (int f = 0; f < 3; ++f) d.view.fingers[f].in_contact = true;
  const Eigen::Vector3d r_point = d.Tick().task.fingers[3].target;
  EXPECT_EQ(out.task.fingers[0].primitive, Primitive::kComposite);
  EXPECT_EQ(out.task.fingers[3].primitive, Primitive::kPosition);
  d.Event(EventType::kTargetReached, 3);
  const Eigen::Vector3d further = d.Tick().task.fingers[3].target;
  EXPECT_NEAR((further - r_point).norm(), 0.01, 1e-9);
  EXPECT_LT((further - d.view.object.translation()).norm(),
            (r_point - d.view.object.translation()).norm());
  d.view.fingers[3].in_contact = true;
  d.Tick();
  d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Gripping);
  d.view.grasp_stable = true;
  d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Releasing);
  bool released = false;
  for (int i = 0; i < 30; ++i) released |= d.Tick().sim == SimRequest::kRelease;
  EXPECT_TRUE(released);
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Settling);
  for (int i = 0; i < 60; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  EXPECT_EQ(d.sup.task_name(), "rotate");
  EXPECT_EQ(d.sup.regrasp().last_action(), "A1 TFMR rotate");
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.2, 1e-12);
  const Eigen::AngleAxisd turn(out.task.object_target.linear());
  EXPECT_NEAR(turn.angle(), 0.2, 1e-9);
  EXPECT_NEAR(std::abs(turn.axis().x()), 1.0, 1e-9);
  d.Event(EventType::kMotionDone);
  d.Tick();
  EXPECT_EQ(d.sup.task_name(), "rotate_back");
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.0, 1e-9);
  EXPECT_TRUE(out.task.object_target.linear().isIdentity(1e-9));
  d.Event(EventType::kMotionDone);
  d.Tick();
  EXPECT_EQ(d.sup.task_name(), "hold");
  bool stopped = false;
  for (int i = 0; i < 120; ++i) stopped |= d.Tick().sim == SimRequest::kStop;
  EXPECT_TRUE(d.sup.finished());
  EXPECT_TRUE(stopped);
}

TEST(SupervisorTest, APTaskThatEndsOutOfItsExitStateIsReported) {
  // The ring finger's first PTask must end touching the object (its exit FIstate).
  TaskFile tasks = Load("fig9_explore");
  PTask& slide = tasks.tasks[0].fingers.at("R")[0];
  slide.exit.contact = ContactState::kTouching;
  Driver d(std::move(tasks), TaskParams{});
  d.Grasp();
  ASSERT_EQ(d.sup.task_name(), "explore_ring");
  d.view.fingers[3].in_contact = false;  // it slid off
  std::string notes;
  for (int i = 0; i < 200 && notes.find("exit state") == std::string::npos; ++i) {
    d.Tick();
    notes += d.sup.note();
  }
  EXPECT_NE(notes.find("finger R is not in its exit state"), std::string::npos) << notes;
}

TEST(SupervisorTest, LostGripContactPausesRegripsAndResumes) {
  Driver d("fig8_rotate");
  d.Grasp();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  d.view.object.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()).toRotationMatrix();
  d.view.fingers[1].in_contact = false;
  d.Event(EventType::kContactLost, 1);
  const SupervisorOutput& out = d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  EXPECT_EQ(d.sup.recoveries(), 1);
  // The motion pauses where the object is; everyone grips.
  EXPECT_TRUE(out.task.object_target.linear().isApprox(d.view.object.linear()));
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.05, 1e-9);
  for (const auto& f : out.task.fingers) EXPECT_EQ(f.primitive, Primitive::kComposite);
  d.view.fingers[1].in_contact = true;
  for (int i = 0; i < 20; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  // The rotation resumes toward the same goal: 0.2 rad in all.
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.2, 1e-9);
}

TEST(SupervisorTest, SilentProcessHoldsTheGraspAndGraspLostFails) {
  Driver d("fig8_rotate");
  d.Grasp();
  d.sup.SetProcessLost(true, "dmpl_ik");
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Holding);
  EXPECT_TRUE(d.sup.holding());
  EXPECT_NE(d.sup.note().find("dmpl_ik"), std::string::npos);
  d.sup.SetProcessLost(false, "dmpl_ik");
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  d.Event(EventType::kGraspLost);
  d.Tick();
  EXPECT_TRUE(d.sup.failed());
  // The STOP after stop_after_s (0.5 s), and again every 0.5 s while reports keep coming (a STOP
  // lost on its way: the simulator runs on).
  std::vector<double> stops;
  for (int i = 0; i < 160; ++i) {
    if (d.Tick().sim == SimRequest::kStop) stops.push_back(d.view.time_s);
  }
  ASSERT_EQ(stops.size(), 3u);
  EXPECT_NEAR(stops[1] - stops[0], 0.5, 0.011);
  EXPECT_NEAR(stops[2] - stops[1], 0.5, 0.011);
}

TEST(SupervisorTest, ApproachTimesOutWhenNothingIsTouched) {
  Driver d("fig8_rotate");
  for (int i = 0; i < 1200 && !d.sup.failed(); ++i) d.Tick();
  EXPECT_TRUE(d.sup.failed());
  EXPECT_NE(d.sup.note().find("did not all touch"), std::string::npos);
}

// Drives a gait with the controller's events answered at once; returns the chart's actions.
std::vector<std::string> RunGait(Driver* d) {
  d->Grasp();
  EXPECT_EQ(d->sup.task_name(), "gait");
  std::vector<std::string> actions;
  for (int i = 0; i < 2000 && d->sup.task_name() == "gait"; ++i) {
    const RegraspChart& chart = d->sup.regrasp();
    if (chart.exploring()) {
      for (int f = 0; f < 4; ++f) {
        if (d->sup.roles()[f] == Role::kExplore) d->Event(EventType::kTargetReached, f);
      }
    } else if (chart.rotating()) {
      d->Event(EventType::kMotionDone);
    }
    const std::string before = chart.last_action();
    d->Tick();
    if (chart.last_action() != before) actions.push_back(chart.last_action());
  }
  return actions;
}

// Real time: the noise injector restarts; no report comes for longer than the recovery timeout
// (the heartbeat monitor makes the supervisor hold meanwhile). When the senses come back, the
// recovery is timed from then, not from before the gap: the grasp is taken up again.
TEST(SupervisorTest, TimeWithoutSensesCountsAgainstNoTimeout) {
  Driver d("fig8_rotate");
  d.Grasp();
  d.sup.SetProcessLost(true, "dmpl_noise");
  d.sup.SetProcessLost(false, "dmpl_noise");
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  d.Tick(SupervisorParams{}.recovery_timeout_s + 1.0);  // the first report after the gap
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  for (int i = 0; i < 20; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  EXPECT_NE(d.sup.note().find("resumed"), std::string::npos);
  // Without the gap being a gap (reports every 10 ms all along), the same wait is a timeout.
  Driver late("fig8_rotate");
  late.Grasp();
  late.sup.SetProcessLost(true, "dmpl_noise");
  late.sup.SetProcessLost(false, "dmpl_noise");
  late.view.grasp_stable = false;
  for (int i = 0; i < 400; ++i) late.Tick();
  EXPECT_TRUE(late.sup.failed());
  // A gap after the end leaves the note saying why it ended.
  const std::string why = late.sup.note();
  late.Tick(1.0);
  EXPECT_EQ(late.sup.note(), why);
}

TEST(SupervisorTest, GaitRunsThePapersRegraspCycleUntilTheGoal) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kThreeFingers;
  tp.angle = 0.35;  // two steps of 10 deg and a partial one
  Driver d("fig10_gait", tp);
  EXPECT_EQ(RunGait(&d), (std::vector<std::string>{"A2 TFM rotate", "A3 R grip", "A7 M explore",
                                                   "A5 TFR rotate", "A6 M grip", "A10 F explore",
                                                   "A8 TMR rotate", "A9 F grip", "finish"}));
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.35, 1e-9);
  EXPECT_EQ(d.sup.regrasp().regrasps(), 3);
  EXPECT_EQ(d.sup.task_name(), "hold");
}

TEST(SupervisorTest, FourFingerGaitTurnsWithAllFourAfterEachRegrasp) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.angle = 0.35;
  Driver d("fig10_gait", tp);
  EXPECT_EQ(RunGait(&d), (std::vector<std::string>{"A3 R grip", "A1 TFMR rotate", "A7 M explore",
                                                   "A6 M grip", "A1 TFMR rotate", "A10 F explore",
                                                   "A9 F grip", "A1 TFMR rotate", "finish"}));
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.35, 1e-9);
  EXPECT_EQ(d.sup.regrasp().regrasps(), 3);
  EXPECT_EQ(d.sup.task_name(), "hold");
}

TEST(SupervisorTest, GripWhileTurningEndsTheTurnOnlyOnceTheGraspIsStable) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.grip_while_turning = true;
  tp.angle = 0.35;
  Driver d("fig10_gait", tp);
  EXPECT_EQ(RunGait(&d), (std::vector<std::string>{"A3 R grip + A1 TFMR rotate", "A7 M explore",
                                                   "A6 M grip + A1 TFMR rotate", "A10 F explore",
                                                   "A9 F grip + A1 TFMR rotate", "finish"}));
  EXPECT_NEAR(d.sup.rotation_commanded(), 0.35, 1e-9);

  // The object at its goal but the grasp not yet stable: the turn goes on.
  Driver e("fig10_gait", tp);
  e.Grasp();
  e.Tick();
  ASSERT_EQ(e.sup.regrasp().last_action(), "A4 R explore");
  e.Event(EventType::kTargetReached, 3);
  e.Tick();
  ASSERT_EQ(e.sup.regrasp().last_action(), "A3 R grip + A1 TFMR rotate");
  e.view.grasp_stable = false;
  for (int i = 0; i < 10; ++i) {
    e.Event(EventType::kMotionDone);
    e.Tick();
  }
  EXPECT_TRUE(e.sup.regrasp().gripping_while_turning());
  e.view.grasp_stable = true;
  e.Event(EventType::kMotionDone);
  e.Tick();
  EXPECT_EQ(e.sup.regrasp().last_action(), "A7 M explore");
}

// Tips `radius` from the object's centre, 90 deg apart about x (T -z, F +y, M +z, R -y).
void PlaceTips(Driver* d, double radius) {
  const Eigen::Vector3d c = d->view.object.translation();
  d->view.fingers[0].tip = c + Eigen::Vector3d(0, 0, -radius);
  d->view.fingers[1].tip = c + Eigen::Vector3d(0, radius, 0);
  d->view.fingers[2].tip = c + Eigen::Vector3d(0, 0, radius);
  d->view.fingers[3].tip = c + Eigen::Vector3d(0, -radius, 0);
}

// The tips of PlaceTips(d, 0.037) each touching with 1 N, their contacts 2.5 cm from the centre
// (the 2.5 cm sphere, or the middles of the 5 cm cube's faces).
void TouchAtTheirHomes(Driver* d) {
  PlaceTips(d, 0.037);
  const Eigen::Vector3d c = d->view.object.translation();
  for (FingerView& f : d->view.fingers) {
    f.contact = c + (f.tip - c) * (0.025 / 0.037);
    f.force = 1.0;
  }
}

// On its way over its home, R's tip meets the surface: it grips there at once instead of pressing
// on toward its point, inside the object.
TEST(SupervisorTest, AFingerPlacedAgainThatTouchesOnItsWayGripsThere) {
  Driver d("fig8_rotate");
  PlaceTips(&d, 0.037);
  d.Grasp();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  FingerView& r = d.view.fingers[3];
  r.in_contact = false;
  d.Event(EventType::kContactLost, 3);
  for (int i = 0; i < 26; ++i) d.Tick();
  ASSERT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kPosition) << "lifted";
  d.Event(EventType::kTargetReached, 3);
  ASSERT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kPosition) << "on its way over";
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kPosition) << "still on its way";
  }
  r.in_contact = true;
  const FingerTask grip = d.Tick().task.fingers[3];
  EXPECT_EQ(grip.primitive, Primitive::kComposite);
  EXPECT_EQ(grip.role, Role::kGrip);
  for (int i = 0; i < 20; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
}

// Brought in, R's tip stops short of the object (its link on it, or another finger in the way):
// the same point would stop it the same way, so it is lifted at once and placed nearer its base.
TEST(SupervisorTest, AFingerThatStopsShortOfTheSurfaceIsPlacedAgainNearerItsBase) {
  for (const double shift : {0.3, 0.0}) {
    SupervisorParams sp;
    sp.replace_shift_rad = shift;
    Driver d("fig8_rotate", {}, sp);
    PlaceTips(&d, 0.037);
    const Eigen::Vector3d c = d.view.object.translation();
    d.Grasp();
    ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
    FingerView& r = d.view.fingers[3];
    r.tip_axis = Eigen::Vector3d::UnitX();  // its base lies toward the palm (-x)
    r.in_contact = false;
    d.Event(EventType::kContactLost, 3);
    for (int i = 0; i < 26; ++i) d.Tick();
    ASSERT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kPosition) << "lifted";
    d.Event(EventType::kTargetReached, 3);
    d.Tick();
    d.Event(EventType::kTargetReached, 3);
    ASSERT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kComposite) << "brought in";
    // Its tip moves 1 mm in 0.29 s and touches nothing.
    for (int i = 0; i < 29; ++i) {
      r.tip += Eigen::Vector3d(0, 0.001 / 29, 0);
      d.Tick();
    }
    ASSERT_EQ(d.sup.roles()[3], Role::kGrip) << "still coming in";
    for (int i = 0; i < 5; ++i) d.Tick();
    if (shift == 0.0) {
      EXPECT_EQ(d.sup.roles()[3], Role::kGrip) << "without a shift it is given its second";
      continue;
    }
    EXPECT_EQ(d.sup.roles()[3], Role::kFree) << "lifted again";
    EXPECT_NE(d.sup.note().find("placing finger R again: it stopped short of the surface"),
              std::string::npos);
    // Over a point 0.3 rad from its home's, toward its base, as far out as before, and so on,
    // 0.3 rad more each time it stops short, up to 0.6 rad.
    for (const double turned : {0.3, 0.6, 0.6}) {
      d.Event(EventType::kTargetReached, 3);
      const FingerTask over = d.Tick().task.fingers[3];
      ASSERT_EQ(over.primitive, Primitive::kPosition);
      const Eigen::Vector3d expected =
          c + 0.047 * Eigen::Vector3d(-std::sin(turned), -std::cos(turned), 0.0);
      EXPECT_LT((over.target - expected).norm(), 1e-9) << turned;
      d.Event(EventType::kTargetReached, 3);
      ASSERT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kComposite);
      for (int i = 0; i < 31; ++i) d.Tick();
      ASSERT_EQ(d.sup.roles()[3], Role::kFree) << "lifted again";
    }
  }
}

TEST(SupervisorTest, AFingerWhoseLinksMetTheObjectInATurnSitsTheTurnsOut) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.grip_while_turning = true;
  tp.angle = 1.0;
  tp.struck_fingers.enabled = true;
  Driver d("fig10_gait", tp);
  PlaceTips(&d, 0.037);
  d.Grasp();
  auto last = [&] { return d.sup.regrasp().last_action(); };
  d.Tick();
  ASSERT_EQ(last(), "A4 R explore");
  d.Event(EventType::kTargetReached, 3);
  d.Tick();
  ASSERT_EQ(last(), "A3 R grip + A1 TFMR rotate");
  // M's links touch while all four turn: it is marked.
  d.Event(EventType::kLinkContact, 2);
  d.Tick();
  EXPECT_NE(d.sup.note().find("M's links met the object in a turn"), std::string::npos);
  for (int i = 0; i < 10 && last() != "A7 M explore"; ++i) {
    d.Event(EventType::kMotionDone);
    d.Tick();
  }
  ASSERT_EQ(last(), "A7 M explore");
  // M explores; when it grips, the object is held still (a step of 0) while it takes hold.
  const double before = d.sup.rotation_commanded();
  d.Event(EventType::kTargetReached, 2);
  d.Tick();
  ASSERT_EQ(last(), "A6 M grip + A1 TFMR rotate");
  EXPECT_NEAR(d.sup.rotation_commanded(), before, 1e-9);
  for (int i = 0; i < 10 && last() != "A10 F explore"; ++i) {
    d.Event(EventType::kMotionDone);
    d.Tick();
  }
  ASSERT_EQ(last(), "A10 F explore");
  EXPECT_EQ(d.sup.roles()[2], Role::kGrip);  // M holds while F explores
  // F grips and all turn: the turn waits for F's grip, then M lifts off and the others turn.
  d.Event(EventType::kTargetReached, 1);
  d.Tick();
  ASSERT_EQ(last(), "A9 F grip + A1 TFMR rotate");
  EXPECT_EQ(d.sup.roles()[2], Role::kGrip);
  EXPECT_NEAR(d.sup.rotation_commanded(), before, 1e-9);
  for (int i = 0; i < 10 && d.sup.roles()[2] == Role::kGrip; ++i) d.Tick();
  EXPECT_EQ(d.sup.roles()[2], Role::kFree);
  EXPECT_NE(d.sup.note().find("M sits this turn out"), std::string::npos) << d.sup.note();
  EXPECT_GT(d.sup.rotation_commanded(), before + 0.1);
  // The turn done, M is placed again before the order's next (T) explores.
  for (int i = 0; i < 10 && last() == "A9 F grip + A1 TFMR rotate"; ++i) {
    d.Event(EventType::kMotionDone);
    d.Tick();
  }
  EXPECT_EQ(last(), "A7 M explore");
}

TEST(SupervisorTest, ASinkingGripWhileAFingerExploresIsCaughtOnlyWhenAskedOverThePalm) {
  // The controller says the grip sinks along gravity while the first explorer (R) slides: with
  // catch_sinking and the palm up every finger, R too, grips again at once; without it, or with
  // the palm held sideways (gravity along -z), R goes on exploring.
  const Eigen::Vector3d up_palm = -Eigen::Vector3d::UnitX();
  const Eigen::Vector3d sideways = -Eigen::Vector3d::UnitZ();
  for (const auto& [catching, gravity] : {std::pair{true, up_palm}, std::pair{false, up_palm},
                                          std::pair{true, sideways}}) {
    TaskParams tp;
    tp.turn.mode = TurnMode::kFourFingers;
    tp.angle = 0.35;
    SupervisorParams sp;
    sp.catch_sinking = catching;
    Driver d("fig10_gait", tp, sp);
    TouchAtTheirHomes(&d);
    d.view.gravity = gravity;
    d.Grasp();
    for (int i = 0; i < 50 && d.sup.roles()[3] != Role::kExplore; ++i) d.Tick();
    ASSERT_EQ(d.sup.roles()[3], Role::kExplore);
    d.Event(EventType::kSinking);
    const SupervisorOutput& out = d.Tick();
    if (catching && gravity.x() < 0) {
      EXPECT_EQ(d.sup.grasp_state(), GraspState::Recovering);
      EXPECT_EQ(d.sup.note().rfind("recovering: the object sinks out of the grip while R explores",
                                   0), 0u) << d.sup.note();
      for (const auto& f : out.task.fingers) EXPECT_EQ(f.role, Role::kGrip);
    } else {
      EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
      EXPECT_EQ(d.sup.roles()[3], Role::kExplore);
    }
  }
}

TEST(SupervisorTest, AFingerLeavingToExploreSaysWhatTheOthersHoldAgainstGravity) {
  // Gravity toward M (+z): M carries the sphere; F and R hold it by friction alone (0.1 here,
  // 2.5 N a push: 2 * 0.1 * 2.5 = 0.5 N at most) and T pushes the wrong way. Without R the
  // others hold M's push and more; without M, at most F's and R's friction.
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.angle = 0.35;
  tp.support.friction = 0.1;
  Driver d("fig10_gait", tp);
  TouchAtTheirHomes(&d);
  d.view.gravity = Eigen::Vector3d::UnitZ();
  d.Grasp();
  auto held = [&](const std::string& finger) {
    for (int i = 0; i < 200 && d.sup.regrasp().last_action().find(finger + " explore") ==
                                   std::string::npos; ++i) {
      for (int f = 0; f < 4; ++f) {
        if (d.sup.roles()[f] == Role::kExplore) d.Event(EventType::kTargetReached, f);
      }
      if (d.sup.regrasp().rotating()) d.Event(EventType::kMotionDone);
      d.Tick();
    }
    const std::string prefix = finger + " explores; the others hold ";
    EXPECT_EQ(d.sup.note().rfind(prefix, 0), 0u) << d.sup.note();
    return std::stod(d.sup.note().substr(prefix.size()));
  };
  EXPECT_GE(held("R"), 2.5 - 0.005);  // M's push at least
  const double without_m = held("M");
  EXPECT_GT(without_m, 0.4);
  EXPECT_LE(without_m, 0.5 + 0.005);  // printed to the hundredth
}

// The explorer's target for the first step: `steps` steps back about +x from R's home.
void ExpectExplorerBack(const std::string& turn, double steps) {
  TaskParams tp;
  tp.turn = TurnParam::FromYaml(YAML::Node(turn));
  Driver d("fig10_gait", tp);
  PlaceTips(&d, 0.037);  // where a grasp of the 2.5 cm sphere puts them
  const Eigen::Vector3d c = d.view.object.translation();
  d.Grasp();
  const SupervisorOutput& out = d.Tick();
  ASSERT_EQ(d.sup.regrasp().last_action(), "A4 R explore");
  const FingerTask& r = out.task.fingers[3];
  EXPECT_EQ(r.role, Role::kExplore);
  EXPECT_EQ(r.primitive, Primitive::kHybrid);
  EXPECT_NEAR(r.force_n, 0.1, 1e-12);
  const Eigen::Vector3d expected =
      c + Eigen::AngleAxisd(-steps * tp.step, Eigen::Vector3d::UnitX()) *
              Eigen::Vector3d(0, -0.037, 0);
  EXPECT_LT((r.target - expected).norm(), 1e-9) << turn;
}


// A full turn in 0.26 rad steps, three fingers turning while the fourth slides.
TaskParams ContinuousGait() {
  TaskParams tp;
  tp.turn.mode = TurnMode::kContinuous;
  tp.step = 0.26;
  tp.angle = 6.0;
  return tp;
}

TEST(SupervisorTest, GaitStepShrinksWhereTheFingersStandCloseTogether) {
  // Around a 1.5 cm sphere the tip centres stand 2.7 cm from its centre: between two explores
  // the finger an explorer slides back toward rides three steps toward it, and 90 deg less three
  // steps must leave the angle two tips 2.6 cm apart need there (gait.tip_clearance_m).
  const TaskParams tp = ContinuousGait();
  Driver d("fig10_gait", tp);
  const double clearance = Load("fig10_gait").gait.tip_clearance_m;
  ASSERT_GT(clearance, 0.0);
  const double radius = 0.027;
  PlaceTips(&d, radius);
  d.Grasp();
  const SupervisorOutput& out = d.Tick();
  ASSERT_EQ(d.sup.task_name(), "gait");
  const double limit = (M_PI / 2 - 2 * std::asin(clearance / (2 * radius))) / 3;
  ASSERT_LT(limit, tp.step);
  EXPECT_NEAR(d.sup.rotation_commanded(), limit, 1e-9);  // the first step, turned while R explores
  // R goes back half of the three steps it rides, about the object's centre.
  const Eigen::Vector3d c = d.view.object.translation();
  const Eigen::Vector3d expected =
      c + Eigen::AngleAxisd(-1.5 * limit, Eigen::Vector3d::UnitX()) *
              Eigen::Vector3d(0, -radius, 0);
  EXPECT_LT((out.task.fingers[3].target - expected).norm(), 1e-9);
  // M, which turns toward R in this step, ends the step `clearance` from R's point.
  const Eigen::Vector3d m_end =
      c + Eigen::AngleAxisd(limit, Eigen::Vector3d::UnitX()) * Eigen::Vector3d(0, 0, radius);
  EXPECT_GE((out.task.fingers[3].target - m_end).norm(), clearance - 1e-9);
}

TEST(SupervisorTest, GaitStepIsTheTasksAroundALargerObject) {
  const TaskParams tp = ContinuousGait();
  Driver d("fig10_gait", tp);
  PlaceTips(&d, 0.037);  // the 2.5 cm sphere the gait was tuned on
  d.Grasp();
  d.Tick();
  EXPECT_NEAR(d.sup.rotation_commanded(), tp.step, 1e-9);
}

TEST(SupervisorTest, ExplorersPointKeepsClearOfTheFingerItSlidesToward) {
  // M stands closer to R than the others (a grasp that ended up uneven): R's point stops short.
  const TaskParams tp = ContinuousGait();
  Driver d("fig10_gait", tp);
  const double clearance = Load("fig10_gait").gait.tip_clearance_m;
  const Eigen::Vector3d c = d.view.object.translation();
  const double radius = 0.037;
  PlaceTips(&d, radius);
  // M 45 deg from +z toward R (-y), where R's usual point (22.5 deg back from -y) would be 7.5
  // deg from M once M has turned its step: R's point stops `clearance` short of M.
  const double m_angle = 45.0 * M_PI / 180.0;
  d.view.fingers[2].tip = c + Eigen::AngleAxisd(m_angle, Eigen::Vector3d::UnitX()) *
                                  Eigen::Vector3d(0, 0, radius);
  d.Grasp();
  const SupervisorOutput& out = d.Tick();
  ASSERT_EQ(d.sup.task_name(), "gait");
  const double step = d.sup.rotation_commanded();
  EXPECT_NEAR(step, tp.step, 1e-9);  // the tips stand far enough from the axis for the full step
  const Eigen::Vector3d m_end = c + Eigen::AngleAxisd(m_angle + step, Eigen::Vector3d::UnitX()) *
                                        Eigen::Vector3d(0, 0, radius);
  const Eigen::Vector3d target = out.task.fingers[3].target;
  EXPECT_NEAR((target - m_end).norm(), clearance, 1e-6);
  EXPECT_NEAR((target - c).norm(), radius, 1e-9);  // still on its circle about the object
}

// About +x from -y toward +z by `angle`: R's side of the object.
Eigen::Vector3d RoundR(double angle) {
  return Eigen::AngleAxisd(-angle, Eigen::Vector3d::UnitX()) * Eigen::Vector3d(0, -1, 0);
}

// R stands on a face of a prism (faces 0.6 rad apart, their edge along x) and its explore goes
// past the edge it has rolled over: with task.edge_hop it eases where it stands, is lifted,
// moved over its point and brought in to it as any explorer; without, it slides there.
void ExpectStepOverAFeltEdge(bool hop) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.angle = 1.0;
  tp.edge_hop.enabled = hop;
  Driver d("fig10_gait", tp);
  PlaceTips(&d, 0.037);
  const Eigen::Vector3d c = d.view.object.translation();
  const double apothem = 0.025, tip_radius = 0.012;
  const Eigen::Vector3d edge = c + RoundR(0.0) * apothem / std::cos(0.3);
  FingerView& r = d.view.fingers[3];
  r.force = 1.0;
  r.in_contact = true;
  // R's tip rolls over the edge (its contact on it, the normal turning from one face's to the
  // next's), then holds on the first face when the gait begins.
  for (int i = 0; i <= 6; ++i) {
    r.contact = edge;
    r.tip = edge + tip_radius * RoundR(-0.3 + 0.1 * i);
    d.Tick();
  }
  r.contact = c + RoundR(-0.15) * apothem / std::cos(0.15);
  r.tip = r.contact + tip_radius * RoundR(-0.3);
  d.Grasp();
  const FingerTask* task = &d.Tick().task.fingers[3];
  ASSERT_EQ(d.sup.regrasp().last_action(), "A4 R explore");
  EXPECT_EQ(task->role, Role::kExplore);
  EXPECT_EQ(task->primitive, Primitive::kHybrid);
  if (!hop) {
    EXPECT_GT((task->target - r.tip).norm(), 0.01);  // straight for its point, past the edge
    return;
  }
  EXPECT_LT((task->target - r.tip).norm(), 1e-9);  // eased where it stands
  EXPECT_NE(d.sup.note().find("stepping over an edge on its way"), std::string::npos) << d.sup.note();
  for (int i = 0; i < 100 && d.sup.roles()[3] != Role::kFree; ++i) task = &d.Tick().task.fingers[3];
  ASSERT_EQ(d.sup.roles()[3], Role::kFree);  // lifted 1 cm off along the line from the centre
  EXPECT_EQ(task->primitive, Primitive::kPosition);
  const Eigen::Vector3d out = (r.tip - c).normalized();
  EXPECT_LT((task->target - (r.tip + 0.01 * out)).norm(), 1e-9);
  const Eigen::Vector3d lifted = task->target;
  d.Event(EventType::kTargetReached, 3);
  task = &d.Tick().task.fingers[3];
  EXPECT_EQ(d.sup.roles()[3], Role::kFree);  // moved over its point, 1 cm out
  const Eigen::Vector3d over = task->target;
  EXPECT_GT((over - lifted).norm(), 0.01);
  d.Event(EventType::kTargetReached, 3);
  task = &d.Tick().task.fingers[3];
  EXPECT_EQ(task->role, Role::kExplore);  // brought in as an explorer
  EXPECT_EQ(task->primitive, Primitive::kHybrid);
  EXPECT_NEAR(task->force_n, 0.1, 1e-12);
  EXPECT_NEAR((over - task->target).norm(), 0.01, 1e-9);
  EXPECT_NEAR((over - c).norm(), (task->target - c).norm() + 0.01, 1e-3);  // over it, not aside
  // Past the edge: its point lies on the far side of the plane through the centre and the edge.
  EXPECT_GT((task->target - c).dot(Eigen::Vector3d::UnitZ()), 0.0);
  EXPECT_LT((r.tip - c).dot(Eigen::Vector3d::UnitZ()), 0.0);
  d.Event(EventType::kTargetReached, 3);
  d.Tick();
  EXPECT_EQ(d.sup.regrasp().last_action(), "A3 R grip");
}

TEST(SupervisorTest, AnExplorerWhoseWayCrossesAFeltEdgeStepsOverIt) {
  ExpectStepOverAFeltEdge(true);
}

TEST(SupervisorTest, AnExplorerSlidesOverAFeltEdgeUnlessAskedToStep) {
  ExpectStepOverAFeltEdge(false);
}

// The 5 cm cube held at four faces (thumb -z, fore +y, middle +z, ring -y), turned about x by the
// four-finger gait, the controller's events answered at once. In its first explore the ring
// finger slides 1.5 cm over its face (felt flat). Returns its target and the supervisor's note
// when it explores again: as the gait plans it (2 steps of 0.35 rad back about x from its home,
// on the felt surface), 5 mm from the middle finger's face.
std::pair<Eigen::Vector3d, std::string> RingFingersSecondExplore(double margin_m) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.angle = 3.0;
  tp.step = 0.35;
  tp.face_bounds.margin_m = margin_m;
  Driver d("fig10_gait", tp);
  TouchAtTheirHomes(&d);
  const Eigen::Vector3d c = d.view.object.translation();
  d.Grasp();
  int explores = 0;
  for (int i = 0; i < 2000; ++i) {
    const RegraspChart& chart = d.sup.regrasp();
    const std::string before = chart.last_action();
    if (chart.exploring()) {
      if (d.sup.roles()[3] == Role::kExplore && explores == 0) {
        FingerView& r = d.view.fingers[3];
        for (int k = 0; k <= 150; ++k) {  // 1 cm/s
          r.contact = c + Eigen::Vector3d(0.0001 * k, -0.025, 0.0);
          r.tip = r.contact + Eigen::Vector3d(0.0, -0.012, 0.0);
          d.Tick();
        }
      }
      for (int f = 0; f < 4; ++f) {
        if (d.sup.roles()[f] == Role::kExplore) d.Event(EventType::kTargetReached, f);
      }
    } else if (chart.rotating()) {
      d.Event(EventType::kMotionDone);
    }
    const SupervisorOutput& out = d.Tick();
    if (chart.last_action() != before && chart.last_action() == "A4 R explore" && ++explores == 2) {
      return {out.task.fingers[3].target - c, d.sup.note()};
    }
  }
  ADD_FAILURE() << "the ring finger did not explore twice";
  return {};
}

TEST(SupervisorTest, AnExplorerOnAFaceFeltFlatStaysTheMarginInsideItsEdges) {
  const auto [planned, planned_note] = RingFingersSecondExplore(0.0);
  EXPECT_GT(std::abs(planned.z()), 0.019);  // its contact under 6 mm from the next face
  EXPECT_EQ(planned_note.find("inside its face"), std::string::npos) << planned_note;
  const auto [kept, kept_note] = RingFingersSecondExplore(0.009);
  EXPECT_NEAR(std::abs(kept.z()), 0.025 - 0.009, 1e-6);  // 9 mm from the next face
  EXPECT_NEAR(kept.y(), planned.y(), 1e-9);        // moved along its face only
  EXPECT_NEAR(kept.x(), planned.x(), 1e-9);
  EXPECT_NE(kept_note.find("mm further inside its face"), std::string::npos) << kept_note;
}

TEST(SupervisorTest, RecoveryPlacesAFingerThatDoesNotTouchAgain) {
  Driver d("fig8_rotate");
  PlaceTips(&d, 0.037);
  const Eigen::Vector3d c = d.view.object.translation();
  d.Grasp();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  // R lost its contact 30 deg from its home, and does not touch again by itself (a link of it
  // rests on the object).
  d.view.fingers[3].tip =
      c + Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()) * Eigen::Vector3d(0, -0.037, 0);
  d.view.fingers[3].in_contact = false;
  d.Event(EventType::kContactLost, 3);
  d.Tick();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  EXPECT_EQ(d.sup.roles()[3], Role::kGrip);
  for (int i = 0; i < 25; ++i) d.Tick();
  // Lifted off along the line from the centre...
  const FingerTask lift = d.Tick().task.fingers[3];
  EXPECT_EQ(lift.primitive, Primitive::kPosition);
  const Eigen::Vector3d out = (d.view.fingers[3].tip - c).normalized();
  EXPECT_LT((lift.target - (d.view.fingers[3].tip + 0.01 * out)).norm(), 1e-9);
  // ...over its home as far out...
  d.Event(EventType::kTargetReached, 3);
  const FingerTask over = d.Tick().task.fingers[3];
  EXPECT_EQ(over.primitive, Primitive::kPosition);
  EXPECT_LT((over.target - (c + Eigen::Vector3d(0, -0.047, 0))).norm(), 1e-9);
  // ...and in by a grip; the recovery ends when it touches and the grasp is stable.
  d.Event(EventType::kTargetReached, 3);
  EXPECT_EQ(d.Tick().task.fingers[3].primitive, Primitive::kComposite);
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  d.view.fingers[3].in_contact = true;
  for (int i = 0; i < 20; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
}

TEST(SupervisorTest, AGripFingerRestingOnALinkIsPlacedAgainOnItsTip) {
  SupervisorParams sp;
  sp.replace_on_link = true;
  Driver d("fig8_rotate", {}, sp);
  PlaceTips(&d, 0.037);
  for (FingerView& f : d.view.fingers) f.force = f.desired_force = 2.0;
  d.Grasp();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  // M's tip pushes 0.3 of its 2 N: a touch of its link that is over within 0.4 s (a slide
  // brushing the object) is let be.
  d.view.fingers[2].force = 0.3;
  d.Event(EventType::kLinkContact, 2);
  for (int i = 0; i < 40; ++i) d.Tick();
  d.Event(EventType::kLinkReleased, 2);
  for (int i = 0; i < 30; ++i) d.Tick();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  // So is a link that touches while the tip still pushes what it should.
  d.view.fingers[2].force = 1.9;
  d.Event(EventType::kLinkContact, 2);
  for (int i = 0; i < 80; ++i) d.Tick();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  d.Event(EventType::kLinkReleased, 2);
  d.Tick();
  // M rests on a link, its tip pushing 0.3 N: after 0.5 s a recovery begins for it.
  d.view.fingers[2].force = 0.3;
  d.Event(EventType::kLinkContact, 2);
  for (int i = 0; i < 49; ++i) d.Tick();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  for (int i = 0; i < 3 && d.sup.grasp_state() == GraspState::Tasks; ++i) d.Tick();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  EXPECT_EQ(d.sup.recoveries(), 1);
  // At once M is lifted off along the line from the centre, though its tip touches...
  const FingerTask lift = d.Tick().task.fingers[2];
  EXPECT_EQ(lift.primitive, Primitive::kPosition);
  EXPECT_LT((lift.target - (d.view.fingers[2].tip + Eigen::Vector3d(0, 0, 0.01))).norm(), 1e-9);
  EXPECT_NE(d.sup.note().find("placing finger M again: its links touch"), std::string::npos);
  // ...and the others are not: their links touch nothing.
  for (int f : {0, 1, 3}) EXPECT_EQ(d.sup.roles()[f], Role::kGrip);
  // Over its home, in by a grip; the recovery ends once the grasp is stable again.
  d.view.fingers[2].in_contact = false;
  d.Event(EventType::kTargetReached, 2);
  d.Tick();
  d.Event(EventType::kTargetReached, 2);
  EXPECT_EQ(d.Tick().task.fingers[2].primitive, Primitive::kComposite);
  d.view.fingers[2].in_contact = true;
  d.view.fingers[2].force = 2.0;
  for (int i = 0; i < 20; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  // The LINK_RELEASED of the lift was lost on the way: the touch does not begin another, though
  // the tip pushes little again.
  d.view.fingers[2].force = 0.3;
  for (int i = 0; i < 50; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  EXPECT_EQ(d.sup.recoveries(), 1);
}

TEST(SupervisorTest, AnExplorersLinkTouchIsNoRestUntilItGrips) {
  SupervisorParams sp;
  sp.replace_on_link = true;
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.angle = 0.35;
  Driver d("fig10_gait", tp, sp);
  PlaceTips(&d, 0.037);
  for (FingerView& f : d.view.fingers) f.force = f.desired_force = 2.0;
  d.Grasp();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  const int r = 3;
  ASSERT_EQ(d.sup.roles()[r], Role::kExplore);
  // R slides with 0.1 N and a link on the object for 1 s: no rest, it does not grip.
  d.view.fingers[r].force = 0.1;
  d.Event(EventType::kLinkContact, r);
  for (int i = 0; i < 100; ++i) d.Tick();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  // At its point it grips (and all four turn); the link still on it and its tip pushing 0.3 N, a
  // rest begins there: the recovery comes 0.5 s after the grip, not at once.
  d.view.fingers[r].force = 0.3;
  d.Event(EventType::kTargetReached, r);
  for (int i = 0; i < 10 && d.sup.roles()[r] != Role::kGrip; ++i) d.Tick();
  ASSERT_EQ(d.sup.roles()[r], Role::kGrip);
  for (int i = 0; i < 45; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  for (int i = 0; i < 10 && d.sup.grasp_state() == GraspState::Tasks; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Recovering);
  EXPECT_NE(d.sup.note().find("finger R rests on a link"), std::string::npos) << d.sup.note();
}

// R explores; its tip leaves the surface and a link touches (pushing the object 5 mm away).
// With task.explorer_link it is lifted off after `after_s`, brought over its point where the
// object now is and in to it as any explorer, at most `tries` times; without, it slides on.
void ExpectAnExplorerOnItsLinkLiftedOff(bool enabled) {
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.angle = 0.35;
  tp.explorer_link.enabled = enabled;
  Driver d("fig10_gait", tp);
  TouchAtTheirHomes(&d);
  d.Grasp();
  const int r = 3;
  ASSERT_EQ(d.sup.roles()[r], Role::kExplore);
  const Eigen::Vector3d point = d.Tick().task.fingers[r].target;
  const Eigen::Vector3d pushed(0.0, 0.0, 0.005);
  d.view.object.translation() += pushed;
  FingerView& finger = d.view.fingers[r];
  finger.in_contact = false;
  finger.force = 0.0;
  d.Event(EventType::kLinkContact, r);
  for (int i = 0; i < 5; ++i) d.Tick();  // 50 ms: not yet (after_s 0.1 s)
  EXPECT_EQ(d.sup.roles()[r], Role::kExplore);
  const FingerTask* task = nullptr;
  for (int i = 0; i < 10; ++i) task = &d.Tick().task.fingers[r];
  if (!enabled) {
    for (int i = 0; i < 100; ++i) task = &d.Tick().task.fingers[r];
    EXPECT_EQ(task->role, Role::kExplore);
    EXPECT_LT((task->target - point).norm(), 1e-9);
    return;
  }
  ASSERT_EQ(task->role, Role::kFree);  // lifted 1 cm off along the line from the centre
  EXPECT_EQ(task->primitive, Primitive::kPosition);
  const Eigen::Vector3d c = d.view.object.translation();
  EXPECT_LT((task->target - (finger.tip + 0.01 * (finger.tip - c).normalized())).norm(), 1e-9);
  EXPECT_NE(d.sup.note().find("R explores on a link"), std::string::npos) << d.sup.note();
  d.Event(EventType::kTargetReached, r);
  task = &d.Tick().task.fingers[r];
  EXPECT_EQ(task->role, Role::kFree);  // over its point on the object, moved with it
  const Eigen::Vector3d over = task->target;
  d.Event(EventType::kTargetReached, r);
  task = &d.Tick().task.fingers[r];
  EXPECT_EQ(task->role, Role::kExplore);
  EXPECT_EQ(task->primitive, Primitive::kHybrid);
  EXPECT_LT((task->target - (point + pushed)).norm(), 1e-9);
  EXPECT_NEAR((over - task->target).norm(), 0.01, 1e-9);
  // Twice more on its link: lifted once more (tries 2), then it slides on.
  for (int lift = 0; lift < 2; ++lift) {
    for (int i = 0; i < 15; ++i) task = &d.Tick().task.fingers[r];
    EXPECT_EQ(task->role, lift == 0 ? Role::kFree : Role::kExplore) << "lift " << lift;
    for (int hop = 0; hop < 2 && task->role == Role::kFree; ++hop) {
      d.Event(EventType::kTargetReached, r);
      task = &d.Tick().task.fingers[r];
    }
  }
}

TEST(SupervisorTest, AnExplorerOnItsLinkWithItsTipOffIsLiftedToComeAgain) {
  ExpectAnExplorerOnItsLinkLiftedOff(true);
}

TEST(SupervisorTest, AnExplorerOnItsLinkSlidesOnUnlessAsked) {
  ExpectAnExplorerOnItsLinkLiftedOff(false);
}

TEST(SupervisorTest, ALinkRestIsLetBeUnlessAsked) {
  Driver d("fig8_rotate");
  d.Grasp();
  ASSERT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  d.Event(EventType::kLinkContact, 2);
  for (int i = 0; i < 50; ++i) d.Tick();
  EXPECT_EQ(d.sup.grasp_state(), GraspState::Tasks);
  EXPECT_EQ(d.sup.recoveries(), 0);
}

TEST(SupervisorTest, TowardGoalsNoFingerIsTakenFarFromItsHome) {
  // A goal a turn about z away: F and R move toward and away from the palm.
  TaskParams tp;
  tp.turn.mode = TurnMode::kFourFingers;
  tp.step = 0.26;
  tp.max_finger_deviation_rad = 0.35;
  OrientationParam goal;
  goal.q = Eigen::AngleAxisd(1.5, Eigen::Vector3d::UnitZ());
  tp.goals = {goal};
  Driver d("fig10_gait", tp);
  PlaceTips(&d, 0.037);
  const Eigen::Vector3d c = d.view.object.translation();
  d.Grasp();
  const SupervisorOutput& out = d.Tick();
  ASSERT_EQ(d.sup.regrasp().last_action(), "A4 R explore");
  // R goes back 0.35 rad about z, not half the four steps it rides (0.52).
  const Eigen::Vector3d expected =
      c + Eigen::AngleAxisd(-0.35, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(0, -0.037, 0);
  EXPECT_LT((out.task.fingers[3].target - expected).norm(), 1e-6);
  d.view.fingers[3].tip = expected;
  d.Event(EventType::kTargetReached, 3);
  d.Tick();
  EXPECT_EQ(d.sup.regrasp().last_action(), "A3 R grip");
  // F already stands 0.2 rad from its home along the turn: the four turn no more than keeps it
  // within 0.35 (to the step's sixteenths), and F explores next.
  d.view.fingers[1].tip =
      c + Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(0, 0.037, 0);
  for (int i = 0; i < 10 && !d.sup.regrasp().rotating(); ++i) d.Tick();
  ASSERT_TRUE(d.sup.regrasp().rotating());
  EXPECT_GT(d.sup.rotation_commanded(), 0.15 - 0.26 / 16);
  EXPECT_LE(d.sup.rotation_commanded(), 0.15 + 1e-9);
  EXPECT_EQ(d.sup.regrasp().next_explorer(), "F");
}

TEST(SupervisorTest, BadTaskNumbersNameTheKey) {
  auto error = [](auto change) {
    TaskParams tp;
    change(&tp);
    try {
      tp.Validate("exp.yaml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  try {  // a turn mode is parsed once, where the config is read
    TaskParams tp;
    YamlReadArchive::Load(YAML::Load("{turn: two}"), "exp.yaml", "task", &tp);
    ADD_FAILURE() << "turn: two was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'task.turn'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'three' (the paper's)"), std::string::npos) << e.what();
  }
  EXPECT_NE(error([](TaskParams* t) { t->step = 0; }).find("key 'task.step'"), std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->goal_tolerance_rad = 0; }).find("task.goal_tolerance_rad"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->random_goal_separation_rad = 3.1; }).find("exp.yaml"),
            std::string::npos);
  // The chooser's companions without the chooser would do nothing: said, not ignored.
  EXPECT_NE(error([](TaskParams* t) { t->contact_choice.clear_steps = true; })
                .find("key 'task.contact_choice.clear_steps': needs task.contact_choice.enabled"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->contact_choice.spread_rad = 2.0; })
                .find("task.contact_choice.spread_rad"),
            std::string::npos);
  EXPECT_EQ(error([](TaskParams* t) {
              t->contact_choice.enabled = true;
              t->contact_choice.clear_steps = true;
            }),
            "");
  EXPECT_NE(error([](TaskParams* t) { t->explorer_support.check_ride = true; })
                .find("key 'task.explorer_support.check_ride': needs "
                      "task.explorer_support.slack_rad > 0"),
            std::string::npos);
  EXPECT_EQ(error([](TaskParams* t) {
              t->explorer_support.check_ride = true;
              t->explorer_support.slack_rad = 0.35;
            }),
            "");
  EXPECT_NE(error([](TaskParams* t) { t->support.min_observed = 1.2; })
                .find("key 'task.support.min_observed': must not exceed"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->explorer_support.need_weights = -1; })
                .find("task.explorer_support.need_weights"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->edge_hop.move_timeout_s = 0; })
                .find("key 'task.edge_hop.move_timeout_s'"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->edge_hop.lift_m = 0.1; }).find("task.edge_hop.lift_m"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->face_bounds.margin_m = -0.001; })
                .find("key 'task.face_bounds.margin_m'"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->face_bounds.min_angle_rad = 0; })
                .find("key 'task.face_bounds.min_angle_rad'"),
            std::string::npos);
  EXPECT_NE(error([](TaskParams* t) { t->face_surface.clearance_m = 0.1; })
                .find("key 'task.face_surface.clearance_m'"),
            std::string::npos);
  EXPECT_EQ(error([](TaskParams*) {}), "");
}

TEST(SupervisorTest, ExplorerGoesBackAgainstTheRotationToAComfortablePoint) {
  // Half of the steps it rides before it explores again: three of four, or all four.
  ExpectExplorerBack("three", 1.5);
  ExpectExplorerBack("four", 2.0);
}

}  // namespace
}  // namespace dmpl
