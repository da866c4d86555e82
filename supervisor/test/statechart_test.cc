#include <gtest/gtest.h>

#include "supervisor/statechart.h"

namespace dmpl::sc {
namespace {

enum class S { A, B, C };
enum class E { Go, Back, Unknown };
const char* ToString(S s) { return s == S::A ? "A" : s == S::B ? "B" : "C"; }
const char* ToString(E e) { return e == E::Go ? "Go" : e == E::Back ? "Back" : "Unknown"; }

TEST(StateMachineTest, FirstMatchingGuardWinsAndActionsRunBeforeTheStateChanges) {
  bool allow_c = false;
  std::vector<std::string> trace;
  StateMachine<S, E>* self = nullptr;
  StateMachine<S, E> m("test", S::A, {
      {S::A, E::Go, Guard("allow_c", [&] { return allow_c; }),
       Action("to_c", [&] { trace.push_back("to_c"); }), S::C},
      {S::A, E::Go, kAlways, Action("to_b", [&] {
         trace.push_back(std::string("to_b from ") + (self->is(S::A) ? "A" : "?"));
       }), S::B},
      {S::B, E::Back, kAlways, kNone, S::A},
  });
  self = &m;
  EXPECT_TRUE(m.Process(E::Go));
  EXPECT_TRUE(m.is(S::B));
  EXPECT_TRUE(m.Process(E::Back));
  allow_c = true;
  EXPECT_TRUE(m.Process(E::Go));
  EXPECT_TRUE(m.is(S::C));
  EXPECT_EQ(trace, (std::vector<std::string>{"to_b from A", "to_c"}));
}

TEST(StateMachineTest, EventsNoRowAcceptsAreLoggedAndIgnored) {
  std::vector<std::string> log;
  StateMachine<S, E> m("test", S::A, {{S::A, E::Go, kAlways, kNone, S::B}});
  m.set_log([&](const std::string&, const StateMachine<S, E>::Transition& t) {
    log.push_back(std::string(ToString(t.from)) + (t.row ? " fired " : " ignored ") +
                  ToString(t.event));
  });
  EXPECT_FALSE(m.Process(E::Back));
  EXPECT_FALSE(m.Process(E::Unknown));
  EXPECT_TRUE(m.is(S::A));
  EXPECT_TRUE(m.Process(E::Go));
  EXPECT_EQ(log, (std::vector<std::string>{"A ignored Back", "A ignored Unknown", "A fired Go"}));
}

TEST(StateMachineTest, EventsRaisedByAnActionRunAfterTheTransition) {
  StateMachine<S, E>* self = nullptr;
  StateMachine<S, E> m("test", S::A, {
      {S::A, E::Go, kAlways, Action("chain", [&] { self->Process(E::Go); }), S::B},
      {S::B, E::Go, kAlways, kNone, S::C},
  });
  self = &m;
  m.Process(E::Go);
  EXPECT_TRUE(m.is(S::C));
}

TEST(StateMachineTest, AnEventsDataReachesTheActionThatFiresEvenWhenQueued) {
  struct Why {
    std::string reason;
    int finger = -1;
  };
  std::vector<std::string> heard;
  StateMachine<S, E, Why>* self = nullptr;
  using A = StateMachine<S, E, Why>::Action;
  StateMachine<S, E, Why> m("test", S::A, {
      {S::A, E::Go, kAlways, A("raise", [&](const Why& w) {
         heard.push_back(w.reason + " " + std::to_string(w.finger));
         self->Process(E::Go, {"raised by the action", 2});
       }), S::B},
      {S::B, E::Go, kAlways, A("hear", [&](const Why& w) { heard.push_back(w.reason); }), S::C},
      {S::C, E::Back, kAlways, A("plain", [&] { heard.push_back("no data read"); }), S::A},
  });
  self = &m;
  m.Process(E::Go, {"first", 1});
  EXPECT_TRUE(m.is(S::C));
  m.Process(E::Back);
  EXPECT_EQ(heard, (std::vector<std::string>{"first 1", "raised by the action", "no data read"}));
  m.Process(E::Back, {"not accepted in A", 3});  // nobody hears an ignored event's data
  EXPECT_EQ(heard.size(), 3u);
}

TEST(StateMachineTest, DotAndMermaidDrawEveryRow) {
  StateMachine<S, E> m("test", S::A, {{S::A, E::Go, Guard("g", nullptr), Action("act", nullptr), S::B},
                                      {S::B, E::Back, kAlways, kNone, S::A}});
  const std::string dot = m.ToDot();
  EXPECT_NE(dot.find("\"A\" -> \"B\" [label=\"Go [g] / act\"]"), std::string::npos) << dot;
  EXPECT_NE(dot.find("\"B\" -> \"A\" [label=\"Back\"]"), std::string::npos) << dot;
  const std::string mermaid = m.ToMermaid();
  EXPECT_NE(mermaid.find("A --> B: Go [g] / act"), std::string::npos) << mermaid;
}

}  // namespace
}  // namespace dmpl::sc
