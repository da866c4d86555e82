// dmpl_supervisor: the grasp and regrasp statecharts on LCM. Reads sections: run, hand, task,
// supervisor. It answers every DMPL_CONTROLLER_REPORT k (one every controller.node.report_period_ticks)
// with the DMPL_TASK of seq k; in lockstep the controller uses it from tick k + 1, so every task
// takes effect at a defined tick.
//   dmpl_supervisor --dot      prints the charts (grasp; regrasp per task.turn; Graphviz), exits
//   dmpl_supervisor --mermaid  the same in Mermaid, as drawn in the README
#include <cerrno>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>

#include "components/logging/decode.h"
#include "components/runtime/journal.h"
#include "components/runtime/lcm_eigen.h"
#include "components/hand/hand_model.h"
#include "components/kinematics/hand_kinematics.h"
#include "components/runtime/channels.h"
#include "components/runtime/clock.h"
#include "components/runtime/lockstep.h"
#include "components/runtime/node.h"
#include "supervisor/supervisor_node.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/supervisor_status_t.hpp"
#include "dmpl/task_cmd_t.hpp"
#include "supervisor/supervisor.h"
#include "supervisor/supervisor_translation.h"

namespace dmpl {
namespace {

class SupervisorNode : public Node {
 public:
  SupervisorNode(const NodeContext& ctx, std::vector<std::string> fingers, TaskFile tasks,
                 const TaskParams& task_params, const SupervisorParams& params,
                 std::shared_ptr<const ContactChooser> chooser)
      : Node(ctx),
        params_(params),
        fingers_(fingers),
        core_(fingers, std::move(tasks), task_params, params,
              static_cast<uint64_t>(ctx.run.seed), std::move(chooser)) {
    KeepForResend(ctx.run, 4);
    Subscribe(channels::kControllerReport, &SupervisorNode::OnReport, this);
    Subscribe(channels::kHeartbeat, &SupervisorNode::OnHeartbeat, this);
    AddTimer(0.2, [this] { CheckHeartbeats(); });
    if (!ctx.run.journal_dir.empty()) {
      const std::string path = ctx.run.journal_dir + "/" + name() + ".journal";
      replayed_ = Replay(path);
      journal_ = std::make_unique<JournalWriter>(path);
    }
  }

  void OnStart() override {
    if (replayed_ == 0) return;
    // Taken up after a restart: answer the report the loop waits on (if the last answer was
    // lost with the old process) with the same task, and say where the charts are.
    log().warn("restarted: took up the charts from {} journaled inputs, at tick {} ({})",
               replayed_, last_seq_,
               core_.last_action().empty() ? ToString(core_.grasp_state()) : core_.last_action());
    PublishLoop(channels::kTask, last_task_);
    PublishStatus(last_seq_, last_utime_);
  }

 private:
  // The journal's entries: a report answered, or a change of the processes' liveness.
  static constexpr uint8_t kReportEntry = 'R';
  static constexpr uint8_t kLivenessEntry = 'L';

  // Steps the charts through the journal of a supervisor that died; how many inputs it took.
  int Replay(const std::string& path) {
    int cut_short = 0;
    const std::vector<JournalEntry> entries = ReadJournal(path, &cut_short);
    if (cut_short) log().warn("{}: its last entry was cut short (a kill mid-write): left out", path);
    for (const JournalEntry& e : entries) {
      if (e.tag == kReportEntry) {
        controller_status_t m;
        if (!DecodeMessage(e.bytes.data(), static_cast<uint32_t>(e.bytes.size()), &m)) {
          throw std::runtime_error(path + ": a journaled report does not decode");
        }
        Answer(m, false);
      } else if (e.tag == kLivenessEntry && !e.bytes.empty()) {
        core_.SetProcessLost(e.bytes[0] != 0, std::string(e.bytes.begin() + 1, e.bytes.end()));
      } else {
        throw std::runtime_error(path + ": an entry of unknown kind " + std::to_string(e.tag));
      }
    }
    return static_cast<int>(entries.size());
  }

  void Journal(uint8_t tag, const void* data, size_t size) {
    if (journal_ && !journal_->Append(tag, data, size)) {
      log().critical("cannot write the journal '{}': {}; a restart could not take up the "
                     "charts", journal_->path(), std::strerror(errno));
      journal_.reset();
    }
  }

  void OnHeartbeat(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* hb) {
    last_beat_[hb->process] = MonotonicSeconds();
  }

  void CheckHeartbeats() {
    const double now = MonotonicSeconds();
    std::string silent;
    for (const auto& p : params_.required_processes) {
      const auto it = last_beat_.find(p);
      const double since = it == last_beat_.end() ? now - started_ : now - it->second;
      if (since > params_.heartbeat_timeout_s) silent += (silent.empty() ? "" : ", ") + p;
    }
    const bool lost = !silent.empty();
    if (lost != core_.holding() && core_.grasp_state() != GraspState::ObjectHeld) {
      if (lost) log().error("no heartbeat from {}: holding the grasp", silent);
      const std::string who = lost ? silent : std::string("all");
      core_.SetProcessLost(lost, who);
      const std::string entry = std::string(1, lost ? '\1' : '\0') + who;
      Journal(kLivenessEntry, entry.data(), entry.size());
      PublishStatus(last_seq_, last_utime_);
    }
  }

  void OnReport(const lcm::ReceiveBuffer* rbuf, const std::string&, const controller_status_t* m) {
    if (answered_any_ && m->seq <= last_seq_) return;  // a copy of a report already answered
    std::string why = OutOfRange(*m);
    if (answered_any_ && m->seq > last_seq_ + kMaxTicksAhead) {
      why = "tick far ahead of " + std::to_string(last_seq_) + " (forged, or another run's)";
    }
    if (!why.empty()) {
      ++rejected_;
      if (LogThisOccurrence(rejected_)) {
        log().warn("report {} rejected: {} ({} so far)", m->seq, why, rejected_);
      }
      return;
    }
    Answer(*m, true);
    // After the answer: a supervisor killed between the two answers the report again.
    Journal(kReportEntry, rbuf->data, rbuf->data_size);
  }

  // Steps the charts with a report and answers it with a task; `live`: publishes and logs (a
  // replay of the journal only rebuilds the state and the last task).
  void Answer(const controller_status_t& m, bool live) {
    answered_any_ = true;
    const ControllerView view = ToControllerView(m, fingers_);
    const size_t logged = core_.transitions().size();
    const int goals_before = core_.goals().reached();
    const SupervisorOutput& out = core_.Step(view);
    // A request to the simulator rides with the task (task_cmd_t.sim_command): the simulator
    // applies it with the joint command planned from this task, before it steps from tick
    // seq + 1, in every run at the same tick.
    const std::string reason = out.sim == SimRequest::kNone      ? ""
                               : out.sim == SimRequest::kRelease ? "grasp stable"
                                                                 : core_.note();
    if (live) LogStep(view.time_s, logged, goals_before, out.sim, reason);
    last_task_ = ToTaskMessage(out.task, fingers_, m.seq, m.utime, out.sim, reason);
    last_task_.run_id = run_id();
    if (live) {
      PublishLoop(channels::kTask, last_task_);
      if (out.changed || m.seq % params_.status_every_ticks == 0) PublishStatus(m.seq, m.utime);
    }
    last_seq_ = m.seq;
    last_utime_ = m.utime;
    set_tick(m.seq);
  }

  // The transitions a step made, a goal it reached, a request it sends the simulator.
  void LogStep(double time_s, size_t logged, int goals_before, SimRequest sim,
               const std::string& reason) {
    for (size_t i = logged; i < core_.transitions().size(); ++i) {
      log().info("t = {:.3f} s: {}", time_s, core_.transitions()[i]);
    }
    if (core_.goals().reached() != goals_before) {
      log().info("t = {:.3f} s: {}", time_s, core_.note());
    }
    if (sim != SimRequest::kNone) {
      log().info("t = {:.3f} s: asks the simulator to {} ({})", time_s, ToString(sim), reason);
    }
  }

  void PublishStatus(int64_t seq, int64_t utime) {
    PublishRecorded(channels::kSupervisorStatus, ToStatusMessage(core_, seq, utime));
  }

  SupervisorParams params_;
  std::vector<std::string> fingers_;
  Supervisor core_;
  std::map<std::string, double> last_beat_;
  double started_ = MonotonicSeconds();
  int64_t last_seq_ = 0;
  bool answered_any_ = false;
  int64_t rejected_ = 0;
  int64_t last_utime_ = 0;
  task_cmd_t last_task_{};
  std::unique_ptr<JournalWriter> journal_;  // run.journal_dir: the charts' inputs
  int replayed_ = 0;                        // journal entries taken up at the start
};

struct Loaded {
  std::vector<std::string> fingers;
  TaskFile tasks;
  TaskParams task_params;
  SupervisorParams params;
  // task.contact_choice.enabled, task.explorer_support.check_ride, task.face_surface.enabled or
  // supervisor.replace_on_felt_surface
  std::shared_ptr<const ContactChooser> chooser;
};

Loaded Load(const Config& config) {
  Loaded l;
  HandParams hand;
  config.Load("hand", &hand);
  config.Load("task", &l.task_params);
  config.Load("supervisor", &l.params);
  l.task_params.Validate(config.source());
  l.params.Validate(config.source());
  for (const auto& f : hand.fingers) l.fingers.push_back(f.name);
  if (l.fingers.size() != RegraspChart::kFingers) {
    throw ConfigError("config error in " + config.source() + ": key 'hand.fingers': the regrasp "
                      "chart (the paper's S2..S5) explores four fingers; this hand has " +
                      std::to_string(l.fingers.size()));
  }
  l.tasks = LoadTaskFile(ResolveProjectPath(l.task_params.file), l.fingers);
  if (l.task_params.contact_choice.enabled || l.task_params.explorer_support.check_ride ||
      l.task_params.face_surface.enabled || l.params.replace_on_felt_surface) {
    l.chooser = std::make_shared<const ContactChooser>(
        HandModel::Load(hand), l.task_params.contact_choice, l.task_params.support);
  }
  return l;
}

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeSupervisorNode(const NodeContext& ctx) {
  Loaded l = Load(ctx.config);
  return std::make_unique<SupervisorNode>(ctx, l.fingers, std::move(l.tasks),
                                                l.task_params, l.params, std::move(l.chooser));
}

const NodeInfo kSupervisorNode = {"dmpl_supervisor", "run, hand, task, supervisor", MakeSupervisorNode};

}  // namespace dmpl
