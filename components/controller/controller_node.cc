// dmpl_controller: the local manipulation controller on LCM. Reads sections: run, hand, controller.
// In: DMPL_SENSORS (sensed joints, object pose, fingertips), DMPL_TASK.
// Out: DMPL_FINGER_TARGETS; DMPL_CONTROLLER_STATUS every tick (with its events) for logs and
// tools; DMPL_CONTROLLER_REPORT every controller.node.report_period_ticks (with every event since the
// last report) for the supervisor.
// Lockstep: tick k runs when the sensed data of tick k and (controller.node.wait_for_task) the task
// that answers the last report before tick k have arrived, so a task takes effect at a defined
// tick.
#include <iterator>
#include <limits>
#include <map>

#include "components/runtime/lcm_eigen.h"
#include "components/controller/manipulation_controller.h"
#include "components/runtime/channels.h"
#include "components/runtime/lockstep.h"
#include "components/runtime/node.h"
#include "components/controller/controller_node.h"
#include "components/controller/controller_translation.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/task_cmd_t.hpp"

namespace dmpl {
namespace {

class ControllerNode : public Node {
 public:
  ControllerNode(const NodeContext& ctx, HandModel model, const ControllerParams& params)
      : Node(ctx),
        lockstep_(ctx.run.lockstep),
        wait_for_task_(params.node.wait_for_task),
        model_(std::move(model)),
        kin_(model_),
        core_(kin_, params, ctx.run.tick_s),
        report_period_(params.node.report_period_ticks),
        gate_(MakeGate(params.node.wait_for_task, params.node.report_period_ticks,
                       ctx.run.resend_after_s > 0)) {
    KeepForResend(ctx.run, 8);  // targets and reports
    const int nf = kin_.num_fingers();
    targets_.run_id = status_.run_id = run_id();
    task_.fingers.resize(nf);
    sensed_.tips.resize(nf);
    targets_.num_fingers = static_cast<int8_t>(nf);
    targets_.fingers.resize(nf);
    status_.num_fingers = static_cast<int8_t>(nf);
    status_.fingers.resize(nf);
    for (int f = 0; f < nf; ++f) {
      targets_.fingers[f].finger = kin_.finger(f).name();
      status_.fingers[f].finger = kin_.finger(f).name();
    }
    Subscribe(channels::kSensors, &ControllerNode::OnSensors, this);
    Subscribe(channels::kTask, &ControllerNode::OnTask, this);
  }

 private:
  enum Input : size_t { kSensorsIn = 0, kTaskIn = 1 };

  static LockstepGate MakeGate(bool wait_for_task, int report_period, bool consecutive) {
    std::vector<LockstepGate::Input> inputs = {{"sensors", 0, 0}};
    if (wait_for_task) inputs.push_back({"task", -1, 1, report_period});
    return LockstepGate(inputs, consecutive);
  }

  void Arrived(Input input, int64_t seq) {
    if (!lockstep_) {
      // Real time: run on every sensed tick with the latest task.
      if (input == kSensorsIn) Tick(seq);
      return;
    }
    if (input == kTaskIn && !wait_for_task_) return;  // the gate has no task input
    for (const int64_t tick : gate_.Arrive(input, seq)) Tick(tick);
  }

  void OnSensors(const lcm::ReceiveBuffer*, const std::string&, const hand_sensors_t* m) {
    if (lockstep_ && m->seq <= gate_.last_tick()) return;  // a copy of a tick already computed
    if (FarAhead("sensed data", m->seq)) return;
    // Kept by seq: with an actuation delay the simulator runs ahead, and the sensed data of
    // tick k + 1 can arrive while tick k still waits for its task. Fingers the message does not
    // name keep their last reading.
    sensed_by_seq_[m->seq] = ToSensedInput(*m, kin_, sensed_.tips);
    while (sensed_by_seq_.size() > 256) sensed_by_seq_.erase(sensed_by_seq_.begin());
    Arrived(kSensorsIn, m->seq);
  }

  // Lockstep: a seq far past the loop's tick is forged or another run's; adopting it would
  // push the real ticks out of the queues (or, for a task, answer ticks not yet asked).
  bool FarAhead(const char* what, int64_t seq) {
    if (!lockstep_ || gate_.last_tick() < 0 || seq <= gate_.last_tick() + kMaxTicksAhead) {
      return false;
    }
    ++rejected_;
    if (LogThisOccurrence(rejected_)) {
      log().warn("{} for tick {}, far ahead of tick {}: not adopted ({} rejected so far)", what,
                 seq, gate_.last_tick(), rejected_);
    }
    return true;
  }

  void OnTask(const lcm::ReceiveBuffer*, const std::string&, const task_cmd_t* m) {
    if (FarAhead("task", m->seq)) return;
    std::vector<std::string> unknown;
    TaskInput t = ToTaskInput(*m, kin_, &unknown);
    for (const std::string& finger : unknown) {
      log().warn("task for unknown finger '{}' ignored", finger);
    }
    // Kept by seq: tick k uses the answer to tick k - 1 even if the next one arrives first
    // (a replay on several buses can deliver it early).
    tasks_[m->seq] = {std::move(t), m->sim_command};
    while (tasks_.size() > 64) tasks_.erase(tasks_.begin());
    if (m->task_id != last_task_id_) {
      last_task_id_ = m->task_id;
      log().info("task {} '{}'", m->task_id, m->name);
    }
    Arrived(kTaskIn, m->seq);
  }

  void Tick(int64_t tick) {
    const auto in = sensed_by_seq_.find(tick);
    if (in == sensed_by_seq_.end()) {
      // Only a foreign publisher far ahead on DMPL_SENSORS can push it out; the simulator then
      // reports the missing command.
      log().error("tick {}: its sensed data is gone (messages far ahead of it came first)", tick);
      return;
    }
    sensed_ = std::move(in->second);
    sensed_by_seq_.erase(sensed_by_seq_.begin(), std::next(in));
    // The task that answers the last report before this tick (in real time: the newest).
    const int64_t wanted =
        lockstep_ && wait_for_task_ ? tick - 1 : std::numeric_limits<int64_t>::max();
    const auto it = tasks_.upper_bound(wanted);
    targets_.sim_command = 0;
    if (it != tasks_.begin()) {
      const auto& [task_seq, arrived] = *std::prev(it);
      task_ = arrived.input;
      // The task's command to the simulator goes on with the first targets planned from it
      // (lockstep: delivered, or sent again); in real time with every one planned from it, as
      // any of them may be lost (the simulator's RELEASE and STOP may come twice).
      if (task_seq != forwarded_task_seq_ || !lockstep_) targets_.sim_command = arrived.sim_command;
      forwarded_task_seq_ = task_seq;
    }
    const ControllerOutput& out = core_.Step(sensed_, task_);
    FillTargets(out, sensed_, tick, &targets_);
    PublishLoop(channels::kFingerTargets, targets_);
    FillStatus(out, tick, targets_.utime, kin_, &status_);
    LogEvents(tick, out.events);
    PublishRecorded(channels::kControllerStatus, status_);
    // The report: this status with every event since the last one (none may be lost between).
    report_events_.insert(report_events_.end(), status_.events.begin(), status_.events.end());
    if (tick % report_period_ == 0) {
      std::swap(status_.events, report_events_);
      status_.num_events = static_cast<int16_t>(std::min<size_t>(status_.events.size(), 32767));
      status_.events.resize(status_.num_events);
      PublishLoop(channels::kControllerReport, status_);
      report_events_.clear();
    }
    set_tick(tick);
  }

  void LogEvents(int64_t tick, const std::vector<ControllerEvent>& events) {
    for (const ControllerEvent& e : events) {
      if (e.type != EventType::kInputRejected) {
        log().debug("tick {}: {}", tick, e.text);
        continue;
      }
      ++rejected_;
      if (LogThisOccurrence(rejected_)) {
        log().warn("tick {}: {} ({} rejected so far)", tick, e.text, rejected_);
      }
      set_status(heartbeat_t::RUNNING, e.text);
    }
  }

  bool lockstep_;
  bool wait_for_task_;
  HandModel model_;
  HandKinematics kin_;
  ManipulationController core_;
  int report_period_;
  LockstepGate gate_;
  SensedInput sensed_;                             // the tick being computed
  std::map<int64_t, SensedInput> sensed_by_seq_;   // arrived, not yet computed
  TaskInput task_;
  struct ArrivedTask {
    TaskInput input;
    int8_t sim_command = 0;  // task_cmd_t.sim_command
  };
  std::map<int64_t, ArrivedTask> tasks_;  // by seq
  int64_t forwarded_task_seq_ = std::numeric_limits<int64_t>::min();
  int64_t rejected_ = 0;  // sensed inputs rejected (NaN, out of range, far ahead)
  int32_t last_task_id_ = -1;
  finger_targets_t targets_{};
  controller_status_t status_{};
  std::vector<controller_event_t> report_events_;  // since the last report
};

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeControllerNode(const NodeContext& ctx) {
  HandParams hand;
  ControllerParams params;
  ctx.config.Load("hand", &hand);
  ctx.config.Load("controller", &params);
  params.Validate(ctx.config.source());
  return std::make_unique<ControllerNode>(ctx, HandModel::Load(hand), params);
}

const NodeInfo kControllerNode = {"dmpl_controller", "run, hand, controller", MakeControllerNode};

}  // namespace dmpl
