#include "components/runtime/node.h"

#include <poll.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <iostream>

#include <spdlog/sinks/stdout_color_sinks.h>

#include "components/runtime/channels.h"
#include "components/runtime/clock.h"
#include "components/runtime/command_line.h"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/record_ledger_t.hpp"

namespace dmpl {
namespace {

std::atomic<int> g_stop_signal{0};

void OnStopSignal(int sig) { g_stop_signal.store(sig); }

}  // namespace

void InstallStopSignalHandlers() {
  struct sigaction action {};
  action.sa_handler = OnStopSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int StopSignal() { return g_stop_signal.load(); }

std::shared_ptr<spdlog::logger> MakeLogger(const std::string& name) {
  if (auto existing = spdlog::get(name)) return existing;
  auto logger = spdlog::stderr_color_mt(name);
  logger->set_pattern("[%H:%M:%S.%e] [%n] [%^%l%$] %v");
  const char* level = std::getenv("DMPL_LOG_LEVEL");
  logger->set_level(level ? spdlog::level::from_str(level) : spdlog::level::info);
  return logger;
}

namespace {
// Unconfirmed messages kept per channel: ~0.4 s of a 1 kHz lockstep loop at ten times real
// time, eight ledgers' worth.
constexpr size_t kRecordDepth = 4096;
constexpr double kLedgerPeriodS = 0.05;
// How long a stopping node waits for the recorder's receipts, and how often it asks.
constexpr double kReceiptWaitS = 1.0;
constexpr double kFinalLedgerPeriodS = 0.02;
constexpr int kMessagesBetweenTimers = 16;  // in one process (Executor::Spin)
}  // namespace

Node::Node(std::string name, LcmBus* bus)
    : name_(std::move(name)), bus_(bus), logger_(MakeLogger(name_)) {}

Node::~Node() {
  for (int id : subscriptions_) bus_->Unsubscribe(id);
}

void Node::AddTimer(double period_s, std::function<void()> fn, bool while_stopping) {
  timers_.push_back({period_s, MonotonicSeconds() + period_s, std::move(fn), while_stopping});
}

void Node::ConfirmWithRecorder() {
  // In one process nothing is lost.
  if (bus_->in_process()) return;
  record_ = std::make_unique<PublishedRecord>(kRecordDepth);
  Subscribe(channels::kRecordReceipt, &Node::OnReceipt, this);
  AddTimer(kLedgerPeriodS, [this] { PublishLedger(false); });
}

void Node::PublishLedger(bool stopping) {
  const std::vector<LedgerEntry> entries = record_->Ledger();
  if (entries.empty()) return;
  record_ledger_t m;
  m.run_id = run_id_;
  m.utime = WallMicros();
  m.seq = tick_;
  m.publisher = name_;
  m.stopping = stopping;
  m.num_channels = static_cast<int16_t>(entries.size());
  for (const LedgerEntry& e : entries) {
    m.channel.push_back(e.channel);
    m.after_seq.push_back(e.after_seq);
    m.through_seq.push_back(e.through_seq);
    m.count.push_back(e.count);
  }
  bus_->Publish(channels::kRecordLedger, m);
}

void Node::OnReceipt(const lcm::ReceiveBuffer*, const std::string&, const record_receipt_t* m) {
  if (m->publisher != name_) return;
  const Receipt receipt{m->channel, m->complete != 0, m->after_seq, m->through_seq, m->have};
  for (const std::vector<uint8_t>* bytes : record_->Confirm(receipt)) {
    bus_->Publish(m->channel, bytes->data(), static_cast<unsigned>(bytes->size()));
  }
}

bool Node::AwaitsReceipts() const {
  return record_ && record_->heard_recorder() && !record_->AllConfirmed();
}

Node::Node(const NodeContext& ctx) : Node(ctx.name, ctx.bus) {
  run_id_ = ctx.run.run_id;
  if (ctx.run.record_receipts) ConfirmWithRecorder();
}

void Node::CountForeign(const std::string& channel, int64_t run_id) {
  ++foreign_;
  if (!LogThisOccurrence(foreign_)) return;
  if (run_id == 0) {
    log().warn("a message on {} carries no run identity, which this run's loop requires (this "
               "is {:x}); {} not this run's so far, ignored", channel, run_id_, foreign_);
  } else {
    log().warn("a message on {} belongs to another run ({:x}, this is {:x}); {} so far, ignored",
               channel, run_id, run_id_, foreign_);
  }
}

void Node::CountUndecodable(const std::string& channel, const char* type, uint32_t size) {
  ++undecodable_;
  if (LogThisOccurrence(undecodable_)) {
    log().warn("a message on {} is not a {} ({} bytes); {} so far, ignored", channel, type, size,
               undecodable_);
  }
}

void Node::KeepForResend(const RunParams& run, size_t depth) {
  if (bus_->in_process()) return;  // nothing is lost in one process
  resender_ = std::make_unique<Resender>(depth, run.lockstep ? run.resend_after_s : 0.0);
  if (resender_->enabled()) {
    // Also while the node stops: its last messages may still be what the loop waits for.
    AddTimer(run.resend_after_s / 2, [this] { resender_->Poll(MonotonicSeconds()); }, true);
  }
}

void Node::RequestExit(int exit_code) {
  exit_requested_ = true;
  exit_code_ = std::max(exit_code_, exit_code);
}

void Node::set_status(int8_t state, std::string text) {
  state_ = state;
  status_text_ = std::move(text);
}

Executor::Executor(LcmBus* bus, double heartbeat_period_s)
    : bus_(bus), heartbeat_period_s_(heartbeat_period_s) {}

void Executor::Add(Node* node) { nodes_.push_back(node); }

void Executor::PublishHeartbeats(int8_t state) {
  for (Node* node : nodes_) {
    heartbeat_t hb;
    hb.run_id = node->run_id_;
    hb.utime = WallMicros();
    hb.seq = node->tick_;
    hb.process = node->name_;
    hb.pid = static_cast<int32_t>(getpid());
    hb.state = node->state_ == heartbeat_t::FAULT ? heartbeat_t::FAULT : state;
    hb.count = node->heartbeats_++;
    hb.status = node->status_text_;
    bus_->Publish(channels::kHeartbeat, hb);
  }
}

void Executor::SpinOnce(double max_wait_s, bool stopping) {
  // Wait for traffic, but not past the next timer.
  const double now = MonotonicSeconds();
  double next = now + max_wait_s;
  for (Node* node : nodes_) {
    for (const auto& t : node->timers_) {
      if (!stopping || t.while_stopping) next = std::min(next, t.next_s);
    }
  }
  const int timeout_ms = std::clamp(static_cast<int>((next - now) * 1000.0) + 1, 0, 50);
  if (InProcessQueue* queue = bus_->in_process()) {
    // One message, as LCM's handle() would; with none queued only a timer can publish one.
    if (!queue->DeliverOne()) poll(nullptr, 0, timeout_ms);
  } else if (!HandleNetworkTraffic(timeout_ms)) {
    return;
  }
  RunTimers(stopping);
}

bool Executor::HandleNetworkTraffic(int timeout_ms) {
  // Every bus subscribed on, the management bus first; a readable one has a message to handle.
  if (listened_.size() != bus_->listened().size()) {
    listened_ = bus_->listened();
    fds_.clear();
    for (lcm::LCM* l : listened_) fds_.push_back({l->getFileno(), POLLIN, 0});
  }
  const int ready = poll(fds_.data(), fds_.size(), timeout_ms);
  if (ready < 0 && errno != EINTR) {
    nodes_.front()->log().error("poll on the LCM buses failed; stopping");
    nodes_.front()->RequestExit(1);
    return false;
  }
  for (size_t i = 0; ready > 0 && i < listened_.size(); ++i) {
    if (fds_[i].revents & POLLIN) listened_[i]->handle();
  }
  return true;
}

void Executor::RunTimers(bool stopping) {
  const double now = MonotonicSeconds();
  for (Node* node : nodes_) {
    for (auto& t : node->timers_) {
      if (now >= t.next_s && (!stopping || t.while_stopping)) {
        t.next_s = std::max(t.next_s + t.period_s, now);
        t.fn();
      }
    }
  }
}

void Executor::AwaitReceipts() {
  auto waiting = [&] {
    return std::any_of(nodes_.begin(), nodes_.end(), [](Node* n) { return n->AwaitsReceipts(); });
  };
  if (!waiting()) return;
  for (Node* node : nodes_) node->stopping_ = true;
  const double t0 = MonotonicSeconds();
  double next_ledger = t0;
  while (waiting() && MonotonicSeconds() - t0 < kReceiptWaitS) {
    if (MonotonicSeconds() >= next_ledger) {
      for (Node* node : nodes_) {
        if (node->AwaitsReceipts()) node->PublishLedger(true);
      }
      next_ledger = MonotonicSeconds() + kFinalLedgerPeriodS;
    }
    SpinOnce(kFinalLedgerPeriodS, true);
  }
  for (Node* node : nodes_) {
    if (node->AwaitsReceipts()) {
      node->log().warn("stopped before the recorder confirmed all it sent (waited {:.1f} s): "
                       "its log may lack some of this node's last messages", kReceiptWaitS);
    }
  }
}

int Executor::Spin() {
  for (Node* node : nodes_) node->OnStart();
  PublishHeartbeats(heartbeat_t::RUNNING);
  double next_heartbeat = MonotonicSeconds() + heartbeat_period_s_;
  auto any_exit = [&] {
    return std::any_of(nodes_.begin(), nodes_.end(), [](Node* n) { return n->exit_requested_; });
  };
  InProcessQueue* queue = bus_->in_process();
  int burst = 0;
  while (StopSignal() == 0 && !any_exit()) {
    // In one process, a few messages between looks at the clock: timers run on wall time and
    // a tick is a handful of messages, so they still fire within a tick or two.
    if (queue != nullptr && burst < kMessagesBetweenTimers && queue->DeliverOne()) {
      ++burst;
      continue;
    }
    burst = 0;
    SpinOnce(std::max(0.0, next_heartbeat - MonotonicSeconds()), false);
    if (MonotonicSeconds() >= next_heartbeat) {
      PublishHeartbeats(heartbeat_t::RUNNING);
      next_heartbeat = MonotonicSeconds() + heartbeat_period_s_;
    }
  }
  PublishHeartbeats(heartbeat_t::STOPPING);
  AwaitReceipts();
  for (Node* node : nodes_) node->OnStop();
  int code = 0;
  for (Node* node : nodes_) code = std::max(code, node->exit_code_);
  if (const int sig = StopSignal(); sig != 0 && code == 0) {
    // Asked to stop: a clean shutdown, not a failure.
    return 0;
  }
  return code;
}

void AddConfigFlags(CLI::App& app, NodeCommandLine* cl) {
  app.add_option("--config", cl->config_file, "the config or experiment file (YAML)")
      ->type_name("FILE");
  // One value per flag: a word after it is not a second value.
  app.add_option("--params", cl->params_files,
                 "a parameter file laid over the config (repeatable, in order)")
      ->type_name("FILE")
      ->allow_extra_args(false);
  app.add_option("--set", cl->set_overrides,
                 "one key of the config overridden, e.g. run.seed=3 (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

void AddNodeFlags(CLI::App& app, NodeCommandLine* cl) {
  AddConfigFlags(app, cl);
  app.add_option("--lcm-url", cl->lcm_url, "the LCM URL (default: run.lcm_url, $LCM_DEFAULT_URL)")
      ->type_name("URL");
  app.add_option("--name", cl->name, "the node's name in heartbeats and logs")
      ->type_name("NAME");
  app.add_flag("--print-config", cl->print_config, "print the resolved config as YAML and exit");
  app.add_flag("--check", cl->check, "validate the config, build the node, and exit");
}

int RunNode(const NodeCommandLine& cl, const NodeInfo& info) {
  const std::string default_name = info.name;
  NodeContext ctx;
  try {
    ctx.name = cl.name.empty() ? default_name : cl.name;
    ctx.config = Config::Resolve(cl.config_file, cl.params_files, cl.set_overrides);
    ctx.config.Load("run", &ctx.run);
    ctx.run.Validate(ctx.config.source());
  } catch (const std::exception& e) {
    std::cerr << default_name << ": " << e.what() << "\n";
    return 2;
  }
  auto log = MakeLogger(ctx.name);
  const std::string url = ResolveLcmUrl(cl.lcm_url, ctx.run);
  // --check builds the node on an in-process bus: it validates, and needs no network.
  LcmBus bus(cl.check ? std::string("memq://") : url, ctx.run.channel_buses);
  if (!bus.good()) {
    log->critical("cannot open LCM at '{}' (is there a multicast route on lo? see README)", url);
    return 3;
  }
  ctx.bus = &bus;
  std::unique_ptr<Node> node;
  try {
    node = info.make(ctx);
  } catch (const std::exception& e) {
    log->critical("{}", e.what());
    return 2;
  }
  if (cl.print_config) {
    std::cout << YAML::Dump(ctx.config.root()) << "\n";
    return 0;
  }
  if (cl.check) {
    std::cout << ctx.name << ": configuration OK (" << ctx.config.source() << ")\n";
    return 0;
  }
  InstallStopSignalHandlers();
  log->info("started (pid {}, lcm {}, {})", getpid(), url,
            ctx.run.lockstep ? "lockstep" : "real time");
  Executor executor(&bus, ctx.run.heartbeat_period_s);
  executor.Add(node.get());
  const int code = executor.Spin();
  rusage cpu{};
  getrusage(RUSAGE_SELF, &cpu);
  log->info("stopped (exit code {}); cpu time user {:.3f} s, system {:.3f} s", code,
            cpu.ru_utime.tv_sec + cpu.ru_utime.tv_usec * 1e-6,
            cpu.ru_stime.tv_sec + cpu.ru_stime.tv_usec * 1e-6);
  return code;
}

int RunNodeMain(int argc, char** argv, const NodeInfo& info) {
  CLI::App app{std::string(info.name) + ": a node of the dmpl loop; it reads the config sections " +
                   info.reads,
               info.name};
  NodeCommandLine cl;
  AddNodeFlags(app, &cl);
  if (const auto code = ParseCommandLine(app, argc, argv)) return *code;
  return RunNode(cl, info);
}

}  // namespace dmpl
