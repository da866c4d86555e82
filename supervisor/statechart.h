#pragma once
// A small statechart engine in the style of Boost.SML: the chart is a transition table, one row
// per transition, read top to bottom; the first row whose state and event match and whose guard
// holds fires (action, then the new state). An event no row accepts in the current state is
// logged and ignored. A transition log hook, is(state) for tests, and a DOT export to draw it.
//
//   using namespace dmpl::sc;
//   StateMachine<State, Event> chart("regrasp", State::S1, {
//     // from       event            guard               action              to
//     {State::S1,  Event::Start,    Guard("next is R", ...), Action("A4 R explore", ...), State::S2},
//   });
//
// State and Event are enums; the caller provides `const char* ToString(State)` and
// `const char* ToString(Event)` (found by argument-dependent lookup). An event may carry data
// (the third parameter, e.g. a reason and a finger): Process(event, data) hands it to the action
// that fires, as Boost.SML hands an action its event.
#include <cstddef>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace dmpl::sc {

struct Guard {
  Guard() = default;
  Guard(std::string name, std::function<bool()> fn) : name(std::move(name)), fn(std::move(fn)) {}
  std::string name;
  std::function<bool()> fn;  // empty: always
  bool operator()() const { return !fn || fn(); }
};

struct NoData {};

// An action reads the data its event carries, or ignores it.
template <typename Data>
struct BasicAction {
  BasicAction() = default;
  BasicAction(std::string name, std::function<void(const Data&)> fn)
      : name(std::move(name)), fn(std::move(fn)) {}
  BasicAction(std::string name, std::function<void()> fn)
      : name(std::move(name)), fn([f = std::move(fn)](const Data&) {
          if (f) f();
        }) {}
  BasicAction(std::string name, std::nullptr_t) : name(std::move(name)) {}  // drawn, does nothing
  std::string name;
  std::function<void(const Data&)> fn;  // empty: nothing
  void operator()(const Data& data) const {
    if (fn) fn(data);
  }
};
using Action = BasicAction<NoData>;

inline const Guard kAlways{};
inline const Action kNone{};

template <typename State, typename Event, typename Data = NoData>
class StateMachine {
 public:
  using Action = BasicAction<Data>;
  struct Row {
    State from;
    Event event;
    Guard guard;
    Action action;
    State to;
  };
  struct Transition {
    State from;
    Event event;
    const Row* row;  // nullptr: the event was not accepted
  };
  using Log = std::function<void(const std::string& chart, const Transition&)>;

  StateMachine(std::string name, State initial, std::vector<Row> table)
      : name_(std::move(name)), initial_(initial), state_(initial), table_(std::move(table)) {}

  // Processes one event with its data. Returns true when a transition fired. Events raised by an
  // action (call Process from inside it) are queued and run after the current transition.
  bool Process(Event event, Data data = {}) {
    if (processing_) {
      queue_.emplace_back(event, std::move(data));
      return false;
    }
    processing_ = true;
    bool fired = Dispatch(event, data);
    while (!queue_.empty()) {
      const std::pair<Event, Data> next = std::move(queue_.front());
      queue_.erase(queue_.begin());
      Dispatch(next.first, next.second);
    }
    processing_ = false;
    return fired;
  }

  bool is(State s) const { return state_ == s; }
  State state() const { return state_; }
  const std::string& name() const { return name_; }
  void set_log(Log log) { log_ = std::move(log); }
  void Reset() { state_ = initial_; }
  const std::vector<Row>& table() const { return table_; }

  // Mermaid (GitHub draws it): one arrow per row labelled "event [guard] / action".
  std::string ToMermaid() const {
    std::ostringstream os;
    os << "stateDiagram-v2\n    [*] --> " << ToString(initial_) << "\n";
    for (const Row& r : table_) {
      os << "    " << ToString(r.from) << " --> " << ToString(r.to) << ": " << ToString(r.event);
      if (!r.guard.name.empty()) os << " [" << r.guard.name << "]";
      if (!r.action.name.empty()) os << " / " << r.action.name;
      os << "\n";
    }
    return os.str();
  }

  // Graphviz: states as nodes, one edge per row labelled "event [guard] / action".
  std::string ToDot() const {
    std::ostringstream os;
    os << "digraph \"" << name_ << "\" {\n  rankdir=LR;\n  node [shape=box, style=rounded];\n";
    os << "  __start [shape=point];\n  __start -> \"" << ToString(initial_) << "\";\n";
    for (const Row& r : table_) {
      os << "  \"" << ToString(r.from) << "\" -> \"" << ToString(r.to) << "\" [label=\""
         << ToString(r.event);
      if (!r.guard.name.empty()) os << " [" << r.guard.name << "]";
      if (!r.action.name.empty()) os << " / " << r.action.name;
      os << "\"];\n";
    }
    os << "}\n";
    return os.str();
  }

 private:
  bool Dispatch(Event event, const Data& data) {
    for (const Row& r : table_) {
      if (r.from != state_ || r.event != event || !r.guard()) continue;
      const State from = state_;
      r.action(data);
      state_ = r.to;
      if (log_) log_(name_, {from, event, &r});
      return true;
    }
    if (log_) log_(name_, {state_, event, nullptr});
    return false;
  }

  std::string name_;
  State initial_;
  State state_;
  std::vector<Row> table_;
  Log log_;
  bool processing_ = false;
  std::vector<std::pair<Event, Data>> queue_;
};

}  // namespace dmpl::sc
