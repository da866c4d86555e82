#include <gtest/gtest.h>

#include <set>

#include "supervisor/regrasp_chart.h"

namespace dmpl {
namespace {

const std::vector<std::string> kHand = {"T", "F", "M", "R"};

// Records what the chart asks for; turns by `step` per Rotate until `goal`.
class Recorder : public RegraspActions {
 public:
  void Explore(const std::string& f) override { calls.push_back("explore " + f); }
  void Rotate(const std::vector<std::string>& grippers) override {
    std::string g;
    for (const std::string& f : grippers) g += f;
    calls.push_back("rotate " + g);
    turned += 1;
  }
  void Grip(const std::string& f) override { calls.push_back("grip " + f); }
  void Finish() override { calls.push_back("finish"); }
  bool GoalReached() const override { return turned >= goal; }
  bool CanTurnWithout(const std::string& f) const override { return three_turn.count(f) > 0; }
  std::vector<std::string> calls;
  std::set<std::string> three_turn;  // kAuto: the explorers the other three can turn without
  int turned = 0;
  int goal = 4;
};

// One scripted event, the state it leads to and the action it takes.
struct Step {
  RegraspEvent event;
  RegraspState state;
  const char* action;
};

void Play(RegraspChart* chart, const std::vector<Step>& script) {
  for (const Step& s : script) {
    EXPECT_TRUE(chart->Process(s.event)) << ToString(s.event);
    EXPECT_TRUE(chart->is(s.state)) << ToString(s.event) << " -> " << ToString(chart->state());
    EXPECT_EQ(chart->last_action(), s.action);
  }
}

TEST(RegraspChartTest, TheFullRMFTCycleOnAScriptedEventStream) {
  Recorder r;
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"});
  using E = RegraspEvent;
  using S = RegraspState;
  Play(&chart, {
      {E::Begin, S::S2, "A4 R explore"},     {E::ExploreReady, S::S2, "A2 TFM rotate"},
      {E::RotateDone, S::S1, "A3 R grip"},   {E::GripStable, S::S3, "A7 M explore"},
      {E::ExploreReady, S::S3, "A5 TFR rotate"}, {E::RotateDone, S::S1, "A6 M grip"},
      {E::GripStable, S::S4, "A10 F explore"},   {E::ExploreReady, S::S4, "A8 TMR rotate"},
      {E::RotateDone, S::S1, "A9 F grip"},   {E::GripStable, S::S5, "A13 T explore"},
      {E::ExploreReady, S::S5, "A11 FMR rotate"}, {E::RotateDone, S::S1, "A12 T grip"},
      {E::GripStable, S::S1, "finish"},
  });
  EXPECT_EQ(chart.regrasps(), 4);
  EXPECT_EQ(r.calls.back(), "finish");
  EXPECT_EQ(r.calls[1], "rotate TFM");
}

TEST(RegraspChartTest, ContinuousTurnsWhileTheExplorerSlidesAndGripsWhenBothAreDone) {
  Recorder r;
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"}, RegraspChart::Turn::kContinuous);
  using E = RegraspEvent;
  using S = RegraspState;
  Play(&chart, {
      {E::Begin, S::S2, "A4 R explore + A2 TFM rotate"}, {E::ExploreReady, S::S1, "A3 R grip"},
      {E::GripStable, S::S3, "A7 M explore + A5 TFR rotate"},
      {E::ExploreReady, S::S1, "A6 M grip"},
      {E::GripStable, S::S4, "A10 F explore + A8 TMR rotate"},
      {E::ExploreReady, S::S1, "A9 F grip"},
      {E::GripStable, S::S5, "A13 T explore + A11 FMR rotate"},
      {E::ExploreReady, S::S1, "A12 T grip"}, {E::GripStable, S::S1, "finish"},
  });
  EXPECT_EQ(r.turned, 4);
  EXPECT_EQ(r.calls[0], "explore R");  // the explorer leaves first, then the three turn
  EXPECT_EQ(r.calls[1], "rotate TFM");
}

TEST(RegraspChartTest, AutoTurnsWithThreeWhenTheyCanElseWithFourAfterTheGrip) {
  // About y, say: F and R sit on the axis, so only while F or R explores can the other three
  // (T and M among them) turn the object.
  Recorder r;
  r.three_turn = {"F", "R"};
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"}, RegraspChart::Turn::kAuto);
  using E = RegraspEvent;
  using S = RegraspState;
  Play(&chart, {
      {E::Begin, S::S2, "A4 R explore + A2 TFM rotate"}, {E::ExploreReady, S::S1, "A3 R grip"},
      {E::GripStable, S::S3, "A7 M explore"}, {E::ExploreReady, S::S1, "A6 M grip"},
      {E::GripStable, S::S1, "A1 TFMR rotate"},
      {E::RotateDone, S::S4, "A10 F explore + A8 TMR rotate"},
      {E::ExploreReady, S::S1, "A9 F grip"}, {E::GripStable, S::S5, "A13 T explore"},
      {E::ExploreReady, S::S1, "A12 T grip"}, {E::GripStable, S::S1, "A1 TFMR rotate"},
      {E::RotateDone, S::S1, "finish"},
  });
  EXPECT_EQ(r.turned, 4);
  EXPECT_FALSE(chart.overlapping());
}

TEST(RegraspChartTest, FourFingerTurnExploresGripsThenTurnsWithAllFourThroughS1) {
  Recorder r;
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"}, RegraspChart::Turn::kFourFingers);
  using E = RegraspEvent;
  using S = RegraspState;
  Play(&chart, {
      {E::Begin, S::S2, "A4 R explore"},     {E::ExploreReady, S::S1, "A3 R grip"},
      {E::GripStable, S::S1, "A1 TFMR rotate"}, {E::RotateDone, S::S3, "A7 M explore"},
      {E::ExploreReady, S::S1, "A6 M grip"}, {E::GripStable, S::S1, "A1 TFMR rotate"},
      {E::RotateDone, S::S4, "A10 F explore"}, {E::ExploreReady, S::S1, "A9 F grip"},
      {E::GripStable, S::S1, "A1 TFMR rotate"}, {E::RotateDone, S::S5, "A13 T explore"},
      {E::ExploreReady, S::S1, "A12 T grip"}, {E::GripStable, S::S1, "A1 TFMR rotate"},
      {E::RotateDone, S::S1, "finish"},
  });
  EXPECT_EQ(chart.regrasps(), 4);
  EXPECT_EQ(r.turned, 4);
  // Nobody turns while a finger explores: a rotation's end there is out of order.
  RegraspChart again(&r, kHand, {"R", "M", "F", "T"}, RegraspChart::Turn::kFourFingers);
  r.goal = 100;
  again.Process(E::Begin);
  EXPECT_FALSE(again.Process(E::RotateDone));
  EXPECT_FALSE(again.Process(E::GripStable));
  EXPECT_TRUE(again.is(S::S2));
}

TEST(RegraspChartTest, GripWhileTurningStartsTheFourFingerTurnWithTheGrip) {
  Recorder r;
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"}, RegraspChart::Turn::kFourFingers,
                     /*grip_turns=*/true);
  using E = RegraspEvent;
  using S = RegraspState;
  Play(&chart, {
      {E::Begin, S::S2, "A4 R explore"},
      {E::ExploreReady, S::S1, "A3 R grip + A1 TFMR rotate"},
      {E::RotateDone, S::S3, "A7 M explore"},
      {E::ExploreReady, S::S1, "A6 M grip + A1 TFMR rotate"},
      {E::RotateDone, S::S4, "A10 F explore"},
      {E::ExploreReady, S::S1, "A9 F grip + A1 TFMR rotate"},
      {E::RotateDone, S::S5, "A13 T explore"},
      {E::ExploreReady, S::S1, "A12 T grip + A1 TFMR rotate"},
      {E::RotateDone, S::S1, "finish"},
  });
  EXPECT_EQ(chart.regrasps(), 4);
  EXPECT_EQ(r.turned, 4);
  EXPECT_EQ(r.calls[1], "grip R");  // the explorer grips, then all four turn
  EXPECT_EQ(r.calls[2], "rotate TFMR");
  EXPECT_FALSE(chart.gripping_while_turning());

  // kAuto: only after an explore that did not turn the object; a GripStable meanwhile is out of
  // order (the turn's end says the grip is done too).
  Recorder a;
  a.three_turn = {"R"};
  a.goal = 100;
  RegraspChart autom(&a, kHand, {"R", "M", "F", "T"}, RegraspChart::Turn::kAuto, true);
  Play(&autom, {
      {E::Begin, S::S2, "A4 R explore + A2 TFM rotate"}, {E::ExploreReady, S::S1, "A3 R grip"},
      {E::GripStable, S::S3, "A7 M explore"},
      {E::ExploreReady, S::S1, "A6 M grip + A1 TFMR rotate"},
  });
  EXPECT_TRUE(autom.gripping_while_turning());
  EXPECT_FALSE(autom.Process(E::GripStable));
  EXPECT_TRUE(autom.Process(E::RotateDone));
  EXPECT_TRUE(autom.is(S::S4));
  EXPECT_EQ(autom.last_action(), "A10 F explore");
}

TEST(RegraspChartTest, EveryRoleChangePassesThroughS1AndOutOfOrderEventsAreIgnored) {
  Recorder r;
  r.goal = 100;
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"});
  EXPECT_FALSE(chart.Process(RegraspEvent::ExploreReady));  // nobody explores yet
  EXPECT_FALSE(chart.Process(RegraspEvent::RotateDone));
  EXPECT_TRUE(chart.is(RegraspState::S1));
  chart.Process(RegraspEvent::Begin);
  EXPECT_TRUE(chart.is(RegraspState::S2));
  EXPECT_FALSE(chart.Process(RegraspEvent::RotateDone));  // not rotating yet
  EXPECT_FALSE(chart.Process(RegraspEvent::GripStable));  // S2 cannot go to S3 directly
  EXPECT_TRUE(chart.is(RegraspState::S2));
  // A contingency aborts the step back to S1; the same finger explores next.
  EXPECT_TRUE(chart.Process(RegraspEvent::Abort));
  EXPECT_TRUE(chart.is(RegraspState::S1));
  EXPECT_EQ(chart.next_explorer(), "R");
  chart.Process(RegraspEvent::GripStable);
  EXPECT_TRUE(chart.is(RegraspState::S2));
}

TEST(RegraspChartTest, LocalRotationIsA1AndTheOrderIsConfigurable) {
  Recorder r;
  RegraspChart chart(&r, kHand, {"T", "F", "M", "R"});
  EXPECT_TRUE(chart.Process(RegraspEvent::LocalRotate));
  EXPECT_EQ(chart.last_action(), "A1 TFMR rotate");
  EXPECT_TRUE(chart.is(RegraspState::S1));
  chart.Process(RegraspEvent::Begin);
  EXPECT_EQ(chart.last_action(), "A4 T explore");
  chart.Process(RegraspEvent::ExploreReady);
  EXPECT_EQ(chart.last_action(), "A2 FMR rotate");
}

TEST(RegraspChartTest, DotExportHasEveryAction) {
  Recorder r;
  RegraspChart chart(&r, kHand, {"R", "M", "F", "T"});
  const std::string dot = chart.ToDot();
  for (int a = 1; a <= 13; ++a) {
    EXPECT_NE(dot.find("A" + std::to_string(a) + " "), std::string::npos) << a;
  }
}

// The chart knows the fingers by the hand's names, whatever they are.
TEST(RegraspChartTest, FingersAreTheHandsOwn) {
  Recorder r;
  RegraspChart chart(&r, {"thumb", "index", "middle", "ring"}, {"ring", "middle", "index", "thumb"});
  chart.Process(RegraspEvent::LocalRotate);
  EXPECT_EQ(r.calls.back(), "rotate thumbindexmiddlering");
  chart.Process(RegraspEvent::Begin);
  EXPECT_EQ(chart.last_action(), "A4 ring explore");
  chart.Process(RegraspEvent::ExploreReady);
  EXPECT_EQ(chart.last_action(), "A2 thumb,index,middle rotate");
  EXPECT_EQ(r.calls.back(), "rotate thumbindexmiddle");
}

}  // namespace
}  // namespace dmpl
