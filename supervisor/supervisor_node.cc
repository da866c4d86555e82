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

namespace dmpl {
namespace {

class SupervisorNode : public Node {
 public:
  SupervisorNode(const NodeContext& ctx, std::vector<std::string> fingers, TaskFile tasks,
                 const TaskParams& task_params, const SupervisorParams& params)
      : Node(ctx),
        params_(params),
        fingers_(fingers),
        core_(fingers, std::move(tasks), task_params, params,
              static_cast<uint64_t>(ctx.run.seed)) {
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
    ControllerView view;
    view.seq = m.seq;
    view.time_s = m.utime * 1e-6;
    view.fingers.resize(fingers_.size());
    for (const auto& fs : m.fingers) {
      const int f = Index(fs.finger);
      if (f < 0) continue;
      view.fingers[f] = {fs.in_contact != 0, fs.force_n, ToVector3(fs.tip_position)};
    }
    view.object = ToPose(m.object_position, m.object_orientation);
    for (const auto& e : m.events) {
      view.events.push_back({static_cast<EventType>(e.type), Index(e.finger), e.value, e.text});
    }
    view.motion_done = m.motion_done;
    view.grasp_stable = m.grasp_stable;
    view.tracking_error_rad = m.tracking_error_rad;
    const size_t logged = core_.transitions().size();
    const int goals_before = core_.goals().reached();
    const SupervisorOutput& out = core_.Step(view);
    if (live) {
      for (size_t i = logged; i < core_.transitions().size(); ++i) {
        log().info("t = {:.3f} s: {}", view.time_s, core_.transitions()[i]);
      }
      if (core_.goals().reached() != goals_before) {
        log().info("t = {:.3f} s: {}", view.time_s, core_.note());
      }
    }
    // A request to the simulator rides with the task (task_cmd_t.sim_command): the simulator
    // applies it with the joint command planned from this task, before it steps from tick
    // seq + 1, in every run at the same tick.
    int8_t sim_command = 0;
    std::string reason;
    if (out.sim != SimRequest::kNone) {
      sim_command = static_cast<int8_t>(out.sim);
      reason = out.sim == SimRequest::kRelease ? "grasp stable" : core_.note();
      if (live) {
        log().info("t = {:.3f} s: asks the simulator to {} ({})", view.time_s, ToString(out.sim),
                   reason);
      }
    }
    last_task_ = MakeTask(out.task, m.seq, m.utime, sim_command, reason);
    if (live) {
      PublishLoop(channels::kTask, last_task_);
      if (out.changed || m.seq % params_.status_every_ticks == 0) PublishStatus(m.seq, m.utime);
    }
    last_seq_ = m.seq;
    last_utime_ = m.utime;
    set_tick(m.seq);
  }

  // Why a report is not one the controller can have sent (NaN, beyond the hand's physical
  // range), or empty.
  static std::string OutOfRange(const controller_status_t& m) {
    const Eigen::Vector3d object = ToVector3(m.object_position);
    if (!object.allFinite() || object.norm() > InputBounds::kWorkspaceRadiusM) {
      return "object estimate outside the hand's workspace";
    }
    for (double q : m.object_orientation) {
      if (!std::isfinite(q)) return "object orientation with NaN";
    }
    for (const auto& f : m.fingers) {
      const Eigen::Vector3d tip = ToVector3(f.tip_position);
      if (!tip.allFinite() || tip.norm() > InputBounds::kWorkspaceRadiusM) {
        return "finger " + f.finger + " tip outside the hand's workspace";
      }
      if (!std::isfinite(f.force_n) || std::abs(f.force_n) > InputBounds::kMaxForceN) {
        return "finger " + f.finger + " force beyond the sensor's range";
      }
    }
    return "";
  }

  int Index(const std::string& finger) const {
    for (size_t f = 0; f < fingers_.size(); ++f) {
      if (fingers_[f] == finger) return static_cast<int>(f);
    }
    return -1;
  }

  task_cmd_t MakeTask(const TaskInput& t, int64_t seq, int64_t utime, int8_t sim_command,
                      const std::string& reason) const {
    task_cmd_t m{};
    m.run_id = run_id();
    m.sim_command = sim_command;
    m.sim_command_reason = reason;
    m.utime = utime;
    m.seq = seq;
    m.task_id = t.task_id;
    m.name = t.name;
    m.has_object_target = t.has_object_target;
    ToArray(Eigen::Vector3d(t.object_target.translation()), m.object_position);
    ToArray(Eigen::Quaterniond(t.object_target.linear()), m.object_orientation);
    m.max_linear_speed = t.max_linear_speed;
    m.max_angular_speed = t.max_angular_speed;
    for (size_t f = 0; f < fingers_.size(); ++f) {
      finger_primitive_t p{};
      p.finger = fingers_[f];
      p.role = static_cast<int8_t>(t.fingers[f].role);
      p.primitive = static_cast<int8_t>(t.fingers[f].primitive);
      p.has_target = t.fingers[f].has_target;
      for (int i = 0; i < 3; ++i) p.target_position[i] = t.fingers[f].target[i];
      p.force_n = t.fingers[f].force_n;
      m.fingers.push_back(p);
    }
    m.num_fingers = static_cast<int8_t>(m.fingers.size());
    return m;
  }

  void PublishStatus(int64_t seq, int64_t utime) {
    supervisor_status_t s{};
    s.utime = utime;
    s.seq = seq;
    s.grasp_state = ToString(core_.grasp_state());
    s.regrasp_state = ToString(core_.regrasp().state());
    s.last_action = core_.regrasp().last_action();
    s.task_name = core_.task_name();
    s.task_index = core_.task_index();
    s.num_tasks = core_.num_tasks();
    s.finger = fingers_;
    for (Role r : core_.roles()) s.role.push_back(static_cast<int8_t>(r));
    s.num_fingers = static_cast<int8_t>(fingers_.size());
    s.rotation_commanded_rad = core_.rotation_commanded();
    s.rotation_goal_rad = core_.rotation_goal();
    s.regrasps = core_.regrasp().regrasps();
    s.recoveries = core_.recoveries();
    s.holding = core_.holding();
    s.finished = core_.finished();
    s.failed = core_.failed();
    s.note = core_.note();
    const GoalSequence& goals = core_.goals();
    s.num_goals = goals.size();
    s.goals_reached = goals.reached();
    s.has_orientation_goal = !goals.empty();
    ToArray(goals.empty() ? Eigen::Quaterniond::Identity() : goals.current(), s.orientation_goal);
    s.goal_error_rad = goals.error_rad();
    PublishRecorded(channels::kSupervisorStatus, s);
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
  return l;
}

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeSupervisorNode(const NodeContext& ctx) {
  Loaded l = Load(ctx.config);
  return std::make_unique<SupervisorNode>(ctx, l.fingers, std::move(l.tasks),
                                                l.task_params, l.params);
}

const NodeInfo kSupervisorNode = {"dmpl_supervisor", "run, hand, task, supervisor", MakeSupervisorNode};

}  // namespace dmpl
