#pragma once
// The component runtime: a Node is the thin LCM side of a component (subscribe, call the core,
// publish). An Executor runs one or more nodes on one LCM instance: one node per process in the
// multi-process mode, all of them on memq:// in the one-process mode.
#include <poll.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <spdlog/spdlog.h>

#include "components/logging/decode.h"
#include "components/runtime/channels.h"
#include "components/runtime/clock.h"
#include "components/runtime/config.h"
#include "components/runtime/lcm_bus.h"
#include "components/runtime/record_confirm.h"
#include "components/runtime/resend.h"
#include "dmpl/record_receipt_t.hpp"

namespace CLI {
class App;
}

namespace dmpl {

struct NodeContext;

// Whether the `count`-th occurrence of a repeated problem is logged: the first five, then every
// thousandth (a flood of bad input floods no log).
inline bool LogThisOccurrence(int64_t count) { return count <= 5 || count % 1000 == 0; }

// Whether a message type carries the run it belongs to (run_id).
template <typename Msg, typename = void>
struct HasRunId : std::false_type {};
template <typename Msg>
struct HasRunId<Msg, std::void_t<decltype(std::declval<Msg>().run_id)>> : std::true_type {};

class Node {
 public:
  Node(std::string name, LcmBus* bus);
  // A node of a run: its name, bus and run identity (run.run_id).
  explicit Node(const NodeContext& ctx);
  virtual ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  const std::string& name() const { return name_; }
  spdlog::logger& log() const { return *logger_; }
  // Publishes a message that is neither kept for resending nor confirmed by the recorder.
  template <typename Msg>
  void Publish(const std::string& channel, const Msg& msg) {
    bus_->Publish(channel, msg);
  }

  // Called once by the executor after every node was constructed (subscriptions exist).
  virtual void OnStart() {}
  // Called once when the executor stops, before destruction.
  virtual void OnStop() {}

  // Subscribes `handler->*method` (LCM's typed handler signature) to `channel`, decoding here
  // rather than in LCM: a message that is not a Msg (garbage, truncated, another type) is
  // counted and logged at a limited rate, where LCM would print every one.
  template <typename Msg, typename Handler>
  void Subscribe(const std::string& channel,
                 void (Handler::*method)(const lcm::ReceiveBuffer*, const std::string&,
                                         const Msg*),
                 Handler* handler) {
    const bool loop = channels::IsLoopChannel(channel);
    // Decoded into the same message each time: its arrays keep their capacity (no allocation
    // a tick). A handler copies what it keeps; it never holds the pointer.
    auto decoding = [this, method, handler, loop, reused = std::make_shared<Msg>()](
                        const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
      if (stopping_ && ch != channels::kRecordReceipt) return;  // awaiting receipts only
      Msg& msg = *reused;
      if (!DecodeMessage(rbuf->data, rbuf->data_size, &msg)) {
        CountUndecodable(ch, Msg::getTypeName(), rbuf->data_size);
        return;
      }
      if constexpr (HasRunId<Msg>::value) {
        if (!OfThisRun(msg.run_id, loop)) {
          CountForeign(ch, msg.run_id);
          return;
        }
      }
      (handler->*method)(rbuf, ch, &msg);
    };
    subscriptions_.push_back(bus_->Subscribe(channel, std::move(decoding)));
  }
  int64_t undecodable() const { return undecodable_; }
  // This run's identity, for the messages the node sends (0: none).
  int64_t run_id() const { return run_id_; }
  // A message of `run_id` is this run's (channels::OfRun).
  bool OfThisRun(int64_t run_id, bool loop_channel) const {
    return channels::OfRun(run_id_, run_id, loop_channel);
  }

  // Runs `fn` every `period_s` seconds of wall time from the executor's loop (and, when
  // `while_stopping`, while the node waits for the recorder's receipts at its stop).
  void AddTimer(double period_s, std::function<void()> fn, bool while_stopping = false);

  // Lockstep over a lossy network: the node's last `depth` messages published with PublishLoop
  // are sent again while the loop stalls (resend.h; run.resend_after_s; off in real time).
  void KeepForResend(const RunParams& run, size_t depth);
  // Publishes a message of the loop (kept for resending when KeepForResend was called).
  template <typename Msg>
  void PublishLoop(const std::string& channel, const Msg& msg) {
    if (!resender_) {
      PublishRecorded(channel, msg);
      return;
    }
    std::vector<uint8_t> bytes = Encode(msg);
    if (record_) record_->Add(channel, msg.seq, bytes);
    resender_->PublishBytes(bus_->For(channel), channel, std::move(bytes), MonotonicSeconds());
  }
  int64_t resent() const { return resender_ ? resender_->resent() : 0; }
  // Publishes a message for the recorder (a status): on a network bus it is kept until the
  // recorder confirms it, and sent again if the recorder lost it (record_confirm.h).
  template <typename Msg>
  void PublishRecorded(const std::string& channel, const Msg& msg) {
    if (!record_) {
      bus_->Publish(channel, msg);
      return;
    }
    std::vector<uint8_t> bytes = Encode(msg);
    bus_->Publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
    record_->Add(channel, msg.seq, std::move(bytes));
  }

  // Ends the executor's loop; the process exits with the largest code any node asked for.
  void RequestExit(int exit_code);
  bool exit_requested() const { return exit_requested_; }
  int exit_code() const { return exit_code_; }

  // What the heartbeat reports.
  void set_tick(int64_t seq) { tick_ = seq; }
  int64_t tick() const { return tick_; }
  void set_status(int8_t state, std::string text);

 private:
  friend class Executor;
  struct Timer {
    double period_s;
    double next_s;
    std::function<void()> fn;
    bool while_stopping;
  };
  // The recorder's side of what this node published (record_confirm.h).
  void ConfirmWithRecorder();
  void PublishLedger(bool stopping);
  void OnReceipt(const lcm::ReceiveBuffer*, const std::string&, const record_receipt_t* m);
  // At the stop: whether to wait for the recorder's receipts.
  bool AwaitsReceipts() const;

  std::string name_;
  LcmBus* bus_;
  std::shared_ptr<spdlog::logger> logger_;
  void CountUndecodable(const std::string& channel, const char* type, uint32_t size);
  void CountForeign(const std::string& channel, int64_t run_id);

  std::vector<Timer> timers_;
  std::unique_ptr<Resender> resender_;
  std::unique_ptr<PublishedRecord> record_;
  bool stopping_ = false;
  std::vector<int> subscriptions_;  // ids on bus_
  int64_t undecodable_ = 0;
  int64_t foreign_ = 0;
  int64_t run_id_ = 0;
  bool exit_requested_ = false;
  int exit_code_ = 0;
  int64_t tick_ = -1;
  int8_t state_ = 0;
  std::string status_text_;
  int64_t heartbeats_ = 0;
};

class Executor {
 public:
  Executor(LcmBus* bus, double heartbeat_period_s);
  void Add(Node* node);
  // Handles LCM traffic and timers until a stop signal or a node asks to exit. Returns the exit
  // code: the largest a node asked for, else 0 (a stop signal included: how a node ends).
  int Spin();

 private:
  void PublishHeartbeats(int8_t state);
  // Handles traffic and the timers due once, waiting at most `max_wait_s` for traffic.
  void SpinOnce(double max_wait_s, bool stopping);
  // A network bus: waits at most `timeout_ms` for traffic and handles what came; false when
  // polling failed (the executor then stops).
  bool HandleNetworkTraffic(int timeout_ms);
  void RunTimers(bool stopping);
  // At the stop: the nodes wait (at most a second) until the recorder confirms what they sent.
  void AwaitReceipts();
  LcmBus* bus_;
  std::vector<lcm::LCM*> listened_;
  std::vector<pollfd> fds_;
  double heartbeat_period_s_;
  std::vector<Node*> nodes_;
};

// Installs SIGINT/SIGTERM handlers that ask every executor in the process to stop.
void InstallStopSignalHandlers();
// The signal that asked to stop, or 0.
int StopSignal();

// A logger named after the process (spdlog), level from $DMPL_LOG_LEVEL (default info).
std::shared_ptr<spdlog::logger> MakeLogger(const std::string& name);

// The command line every node understands (AddNodeFlags):
//   --config FILE  --params FILE (overlay, repeatable)  --set key=value (repeatable)
//   --lcm-url URL  --name NAME  --print-config  --check  --help
struct NodeCommandLine {
  std::string config_file;
  std::vector<std::string> params_files;
  std::vector<std::string> set_overrides;
  std::string lcm_url;
  std::string name;
  bool print_config = false;
  bool check = false;  // validate the configuration, build the node, exit
};
// Adds the flags that say which configuration to resolve (--config, --params, --set) to `app`
// (components/runtime/command_line.h parses it), for tools that resolve a config as nodes do.
void AddConfigFlags(CLI::App& app, NodeCommandLine* cl);
// Adds every flag of a node's command line to `app`.
void AddNodeFlags(CLI::App& app, NodeCommandLine* cl);

// Everything a node factory gets.
struct NodeContext {
  std::string name;
  Config config;
  RunParams run;
  LcmBus* bus;
};

// A kind of node, described once (in its `*_node.cc`): the name of its executable, which is also
// its default node name and what an experiment's `processes[].exec` names; the config sections
// it reads; and how to build it from a resolved config (a ConfigError names file and key).
struct NodeInfo {
  const char* name;
  const char* reads;
  std::unique_ptr<Node> (*make)(const NodeContext&);
};

// Runs the node of a parsed command line: resolves the config (clear errors, exit 2), opens LCM,
// builds the node, spins. Returns the exit code (README, "Exit codes").
int RunNode(const NodeCommandLine& cl, const NodeInfo& node);
// main() of a single-node process: parses the command line (AddNodeFlags), then RunNode.
int RunNodeMain(int argc, char** argv, const NodeInfo& node);

}  // namespace dmpl
