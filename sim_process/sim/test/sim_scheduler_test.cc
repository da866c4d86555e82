// The simulator's loop rules, without physics or a bus: a fake loop records what the scheduler
// asks of it, in order.
#include "sim_process/sim/sim_scheduler.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dmpl {
namespace {

class RecordingLoop : public SimLoop {
 public:
  void PublishTick(int64_t tick) override { Say("publish " + std::to_string(tick)); }
  void ApplyCommand(const JointCommand& c) override { Say("command " + std::to_string(c.seq)); }
  void ApplyControl(const SimControl& c) override {
    Say(std::string("control ") + ToString(c.command));
  }
  bool StepTo(int64_t tick) override {
    Say("step " + std::to_string(tick));
    return tick >= end_tick;
  }
  void Paused(const SimControl&) override { Say("paused"); }
  void Resumed(const SimControl&, double paused_for_s) override {
    Say("resumed after " + std::to_string(static_cast<int>(paused_for_s)));
  }
  void Fault(const std::string& what) override { Say("fault: " + what); }
  void Finished(const SimControl* stop, bool gave_up) override {
    Say(std::string("finished") + (stop != nullptr ? " by stop" : "") +
        (gave_up ? " gave up" : ""));
  }

  // The events since the last call.
  std::vector<std::string> Take() { return std::exchange(events_, {}); }

  int64_t end_tick = 1000000;

 private:
  void Say(std::string e) { events_.push_back(std::move(e)); }
  std::vector<std::string> events_;
};

using Events = std::vector<std::string>;

JointCommand Command(int64_t seq, SimRequest request = SimRequest::kNone) {
  JointCommand c;
  c.seq = seq;
  c.request = request;
  return c;
}

SimControl Control(int64_t seq, SimRequest command) { return SimControl{seq, command, "test"}; }

SimScheduleParams Lockstep(int delay, bool first_tick_waits = false) {
  SimScheduleParams p;
  p.lockstep = true;
  p.command_delay_ticks = delay;
  p.first_tick_waits = first_tick_waits;
  p.tick_timeout_s = 1.0;
  p.max_tick_faults = 2;
  return p;
}

// Answers ticks from..to (inclusive) in order.
void Answer(SimScheduler* s, int64_t from, int64_t to, double now = 0) {
  for (int64_t k = from; k <= to; ++k) {
    ASSERT_EQ(s->OnCommand(Command(k), now), SimScheduler::Verdict::kQueued) << k;
  }
}

TEST(SimScheduler, LockstepStepsOnceTheDueCommandIsIn) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  EXPECT_EQ(loop.Take(), Events{"publish 0"});  // tick 0 is answered before anything moves
  s.OnCommand(Command(0), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 0", "step 1"}));
  s.OnCommand(Command(1), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 1", "step 2"}));
  EXPECT_EQ(s.tick(), 2);
}

TEST(SimScheduler, ACommandActsExactlyTheDelayLater) {
  for (int delay : {1, 3, 7}) {
    RecordingLoop loop;
    SimScheduler s(Lockstep(delay), &loop);
    s.Begin(0);
    // The first d steps hold the initial targets: the simulator runs d ticks ahead.
    Events expected{"publish 0"};
    for (int k = 1; k <= delay; ++k) expected.push_back("step " + std::to_string(k));
    EXPECT_EQ(loop.Take(), expected) << delay;
    // The answer to tick k is applied by the step from k + d.
    for (int k = 0; k < 5; ++k) {
      s.OnCommand(Command(k), 0);
      EXPECT_EQ(loop.Take(), (Events{"command " + std::to_string(k),
                                     "step " + std::to_string(k + delay + 1)}))
          << "delay " << delay << " answer " << k;
    }
  }
}

TEST(SimScheduler, CommandsOfPublishedTicksWaitForTheirTurn) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(2), &loop);
  s.Begin(0);
  loop.Take();  // at tick 2, due 0
  s.OnCommand(Command(2), 0);  // tick 2 is published: kept
  s.OnCommand(Command(1), 0);
  EXPECT_TRUE(loop.Take().empty());
  EXPECT_EQ(s.waiting_commands(), 2u);
  s.OnCommand(Command(0), 0);  // now 0, 1 and 2 apply, one per step
  EXPECT_EQ(loop.Take(), (Events{"command 0", "step 3", "command 1", "step 4", "command 2",
                                 "step 5"}));
}

TEST(SimScheduler, FirstTickWaitsForItsAnswerWhenLostMessagesAreResent) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(2, /*first_tick_waits=*/true), &loop);
  s.Begin(0);
  EXPECT_EQ(loop.Take(), Events{"publish 0"});
  s.OnCommand(Command(0), 0);
  EXPECT_EQ(loop.Take(), (Events{"step 1", "step 2", "command 0", "step 3"}));
}

TEST(SimScheduler, StaleDuplicateAndAheadCommandsAreRefusedAndCounted) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(1), &loop);
  EXPECT_EQ(s.OnCommand(Command(0), 0), SimScheduler::Verdict::kStale);  // before the start
  s.Begin(0);
  Answer(&s, 0, 3);  // tick 5, due 4
  loop.Take();
  EXPECT_EQ(s.OnCommand(Command(2), 0), SimScheduler::Verdict::kStale);  // already applied
  EXPECT_EQ(s.OnCommand(Command(6), 0), SimScheduler::Verdict::kStale);  // not yet published
  EXPECT_EQ(s.OnCommand(Command(5), 0), SimScheduler::Verdict::kQueued);
  EXPECT_EQ(s.OnCommand(Command(5), 0), SimScheduler::Verdict::kStale);  // a duplicate
  EXPECT_TRUE(loop.Take().empty());
  EXPECT_EQ(s.stale(), 4);
  s.OnCommand(Command(4), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 4", "step 6", "command 5", "step 7"}));
}

TEST(SimScheduler, AControlActsBeforeTheStepThatAppliesTheNextTicksCommand) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  Answer(&s, 0, 4);
  loop.Take();
  // Sent in answer to tick 5, with (before) its command.
  EXPECT_TRUE(s.OnControl(Control(5, SimRequest::kRelease), 0));
  s.OnCommand(Command(5), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 5", "step 6"}));
  s.OnCommand(Command(6), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 6", "control release", "step 7"}));
}

TEST(SimScheduler, AControlWithoutSeqActsAtTheNextStepALateOneIsSaidAndApplied) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  Answer(&s, 0, 2);
  loop.Take();
  EXPECT_TRUE(s.OnControl(Control(-1, SimRequest::kHold), 0));
  EXPECT_FALSE(s.OnControl(Control(0, SimRequest::kReset), 0));  // tick 0 is long gone
  s.OnCommand(Command(3), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 3", "control hold", "control reset", "step 4"}));
}

TEST(SimScheduler, TheTasksRequestActsWithItsCommandBeforeTheStep) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  loop.Take();
  s.OnCommand(Command(0, SimRequest::kRelease), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 0", "control release", "step 1"}));
  s.OnCommand(Command(1, SimRequest::kStop), 0);
  EXPECT_EQ(loop.Take(), (Events{"command 1", "finished by stop"}));  // no step after a stop
  EXPECT_TRUE(s.finished());
  s.OnCommand(Command(1), 0);
  EXPECT_TRUE(loop.Take().empty());
}

TEST(SimScheduler, PausedItKeepsCommandsAndStepsOnceResumed) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  loop.Take();
  s.OnControl(Control(-1, SimRequest::kPause), 1);
  s.OnControl(Control(-1, SimRequest::kPause), 2);  // said once
  EXPECT_EQ(loop.Take(), (Events{"paused"}));
  s.OnCommand(Command(0), 3);
  EXPECT_TRUE(loop.Take().empty());
  s.CheckTimeout(100);  // a paused loop waits for no command: no fault
  EXPECT_EQ(s.faults(), 0);
  s.OnControl(Control(-1, SimRequest::kResume), 31);
  EXPECT_EQ(loop.Take(), (Events{"resumed after 30", "command 0", "step 1"}));
  s.OnControl(Control(-1, SimRequest::kResume), 32);
  EXPECT_TRUE(loop.Take().empty());
}

TEST(SimScheduler, AMissingCommandIsAFaultWithItsSeqAndTooManyEndTheRun) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(10.0);
  Answer(&s, 0, 2, 10.0);  // published tick 3 at 10 s
  loop.Take();
  s.CheckTimeout(10.9);
  EXPECT_TRUE(loop.Take().empty());
  s.CheckTimeout(11.0);
  EXPECT_EQ(loop.Take(), Events{"fault: lockstep fault: no JOINT_CMD for seq 3 within 1.000000 s"});
  s.CheckTimeout(11.5);  // counted from the last fault
  EXPECT_TRUE(loop.Take().empty());
  s.OnCommand(Command(3), 11.6);  // an answer restarts the count
  loop.Take();
  s.CheckTimeout(12.5);
  EXPECT_TRUE(loop.Take().empty());
  s.CheckTimeout(12.7);
  EXPECT_EQ(loop.Take(), (Events{"fault: lockstep fault: no JOINT_CMD for seq 4 within 1.000000 s",
                                 "finished gave up"}));
  EXPECT_EQ(s.faults(), 2);
  s.CheckTimeout(20);
  EXPECT_TRUE(loop.Take().empty());
}

TEST(SimScheduler, AResumeRestartsTheWaitForTheDueCommand) {
  RecordingLoop loop;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  s.OnControl(Control(-1, SimRequest::kPause), 0.5);
  s.OnControl(Control(-1, SimRequest::kResume), 50);
  loop.Take();
  s.CheckTimeout(50.5);  // not a fault: the wait began at the resume
  EXPECT_EQ(s.faults(), 0);
}

TEST(SimScheduler, TheRunsEndFinishesTheLoop) {
  RecordingLoop loop;
  loop.end_tick = 2;
  SimScheduler s(Lockstep(0), &loop);
  s.Begin(0);
  Answer(&s, 0, 1);
  EXPECT_EQ(loop.Take(), (Events{"publish 0", "command 0", "step 1", "command 1", "step 2",
                                 "finished"}));
  EXPECT_EQ(s.OnCommand(Command(2), 0), SimScheduler::Verdict::kQueued);
  EXPECT_TRUE(loop.Take().empty());
}

TEST(SimScheduler, RealTimeAppliesEveryDueCommandInOrder) {
  RecordingLoop loop;
  SimScheduleParams p;
  p.lockstep = false;
  p.command_delay_ticks = 1;
  SimScheduler s(p, &loop);
  s.Begin(0);
  EXPECT_EQ(loop.Take(), Events{"publish 0"});  // real time does not wait for commands
  EXPECT_TRUE(s.AdvanceRealTime(0));
  EXPECT_TRUE(s.AdvanceRealTime(0));
  EXPECT_EQ(loop.Take(), (Events{"step 1", "step 2"}));
  EXPECT_EQ(s.OnCommand(Command(3), 0), SimScheduler::Verdict::kAhead);  // never published
  // Due at tick 2: seq <= 1; seq 2 waits for tick 3.
  EXPECT_EQ(s.OnCommand(Command(1), 0), SimScheduler::Verdict::kQueued);
  EXPECT_EQ(loop.Take(), Events{"command 1"});
  EXPECT_EQ(s.OnCommand(Command(2), 0), SimScheduler::Verdict::kQueued);  // due from tick 3
  EXPECT_TRUE(loop.Take().empty());
  EXPECT_TRUE(s.AdvanceRealTime(0));
  EXPECT_EQ(loop.Take(), Events{"step 3"});
  EXPECT_TRUE(s.AdvanceRealTime(0));
  EXPECT_EQ(loop.Take(), (Events{"command 2", "step 4"}));
  s.OnControl(Control(-1, SimRequest::kPause), 0);
  EXPECT_FALSE(s.AdvanceRealTime(0));
  EXPECT_EQ(loop.Take(), Events{"paused"});
}

}  // namespace
}  // namespace dmpl
