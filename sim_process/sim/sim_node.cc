// dmpl_sim: the Bullet hand simulator on LCM. Reads sections: run, hand, sim, object.
//
// Lockstep (run.lockstep): once every process in run.lockstep_participants has sent a heartbeat,
// publish the truth of tick 0; then for each tick k wait for the JOINT_CMD with seq k - d (d =
// sim.command_delay_ticks; before tick d the initial targets hold), step, publish tick k+1.
// While it waits it sends the truth of the last ticks again (run.resend_after_s: a message of the
// loop may have been lost), and tick 1 waits for tick 0's answer. A command that stays missing
// for run.tick_timeout_s is a fault reported with its seq, never a silent hold; after
// run.max_tick_faults faults the simulator gives up (exit 4). A joint command may carry the
// supervisor's request (release, stop), applied with it.
// Real time: step on the wall clock (sim.realtime_rate), use the latest command that is due
// (seq <= k - d), count late ones.
#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <map>

#include "components/runtime/lcm_eigen.h"
#include "components/hand/hand_model.h"
#include "components/runtime/channels.h"
#include "components/runtime/clock.h"
#include "components/runtime/node.h"
#include "sim_process/sim/sim_node.h"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/joint_cmd_t.hpp"
#include "dmpl/sim_control_t.hpp"
#include "dmpl/sim_status_t.hpp"
#include "sim_process/sim/hand_sim.h"

namespace dmpl {
namespace {

constexpr int kExitLockstepFault = 4;

class SimNode : public Node {
 public:
  SimNode(const NodeContext& ctx, HandModel model, const SimParams& sim, const ObjectParams& object)
      : Node(ctx),
        run_(ctx.run),
        view_gate_(ctx.run.view_rate_hz),
        sim_params_(sim),
        model_(std::move(model)),
        sim_(model_, sim, object) {
    Subscribe(channels::kJointCmd, &SimNode::OnJointCmd, this);
    Subscribe(channels::kSimControl, &SimNode::OnSimControl, this);
    Subscribe(channels::kHeartbeat, &SimNode::OnHeartbeat, this);
    for (const auto& p : run_.lockstep_participants) waiting_for_.push_back(p);
    KeepForResend(run_, 4);  // the truths of the ticks that may still be unanswered
    PrepareMessages();
    if (run_.lockstep) {
      AddTimer(0.05, [this] { CheckLockstep(); });
    } else {
      AddTimer(sim_params_.physics.time_step / sim_params_.realtime_rate, [this] { RealTimeStep(); });
    }
    AddTimer(2.0, [this] { ReportProgress(); });
  }

  void OnStart() override {
    set_status(heartbeat_t::STARTING, "waiting for lockstep participants");
    if (run_.lockstep && waiting_for_.empty()) Begin();
    if (!run_.lockstep) Begin();
  }

 private:
  // --- messages -----------------------------------------------------------------------------
  void PrepareMessages() {
    const auto names = model_.actuated_names();
    sensors_msg_.run_id = run_id();
    joint_state_t& joints = sensors_msg_.joints;
    joints.num_joints = static_cast<int16_t>(names.size());
    joints.name = names;
    joints.position.resize(names.size());
    joints.velocity.resize(names.size());
    joints.effort.resize(names.size());
    tactile_t& tactile = sensors_msg_.tactile;
    tactile.num_fingers = static_cast<int8_t>(model_.fingers().size());
    tactile.fingers.resize(model_.fingers().size());
    for (size_t f = 0; f < model_.fingers().size(); ++f) {
      tactile.fingers[f].finger = model_.fingers()[f].name;
    }
  }

  // The truth of this tick, in one message (hand_sensors_t).
  void PublishState() {
    const int64_t utime = std::llround(sim_.time() * 1e6);
    sensors_msg_.utime = utime;
    sensors_msg_.seq = tick_;
    const JointReading j = sim_.joints();
    joint_state_t& joints = sensors_msg_.joints;
    joints.utime = utime;
    joints.seq = tick_;
    joints.position = j.position;
    joints.velocity = j.velocity;
    joints.effort = j.effort;

    const ObjectReading o = sim_.object();
    object_pose_t& pose = sensors_msg_.object;
    pose.utime = utime;
    pose.seq = tick_;
    pose.valid = true;
    ToArray(Eigen::Vector3d(o.pose.translation()), pose.position);
    ToArray(Eigen::Quaterniond(o.pose.linear()), pose.orientation);
    ToArray(o.linear_velocity, pose.linear_velocity);
    ToArray(o.angular_velocity, pose.angular_velocity);

    tactile_t& tactile = sensors_msg_.tactile;
    tactile.utime = utime;
    tactile.seq = tick_;
    const auto& tips = sim_.tactile();
    for (size_t f = 0; f < tips.size(); ++f) {
      fingertip_contact_t& c = tactile.fingers[f];
      c.in_contact = tips[f].in_contact;
      c.force_n = tips[f].force;
      c.num_points = static_cast<int16_t>(tips[f].points);
      for (int i = 0; i < 3; ++i) {
        c.position[i] = tips[f].position[i];
        c.normal[i] = tips[f].normal[i];
      }
    }
    PublishLoop(channels::kSensorsTrue, sensors_msg_);
    if (view_gate_.Due(utime)) {
      lcm(channels::kViewTruth).publish(channels::kViewTruth, &sensors_msg_);
    }
    published_at_ = MonotonicSeconds();
    if (!run_.lockstep) publish_times_[tick_ % kLatencyWindow] = published_at_;
    set_tick(tick_);
    // Status at 10 Hz of simulated time, and whenever something went wrong.
    if (tick_ % std::max<int64_t>(1, std::llround(0.1 / TickSeconds())) == 0) PublishStatus();
  }

  void PublishStatus() {
    sim_status_t s{};
    s.utime = std::llround(sim_.time() * 1e6);
    s.seq = tick_;
    s.sim_time_s = sim_.time();
    s.lockstep = run_.lockstep;
    s.paused = paused_;
    s.object_held = sim_.object_held();
    s.steps = sim_.steps();
    s.faults = faults_;
    s.rejected_commands = rejected_;
    s.late_commands = late_;
    s.step_us = step_us_;
    s.last_fault = last_fault_;
    lcm(channels::kSimStatus).publish(channels::kSimStatus, &s);
  }

  double TickSeconds() const { return sim_params_.physics.time_step * sim_params_.steps_per_tick; }

  // --- lockstep -----------------------------------------------------------------------------
  void OnHeartbeat(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* hb) {
    if (started_) return;
    for (auto it = waiting_for_.begin(); it != waiting_for_.end(); ++it) {
      if (*it == hb->process) {
        waiting_for_.erase(it);
        break;
      }
    }
    if (waiting_for_.empty()) Begin();
  }

  void Begin() {
    if (started_) return;
    started_ = true;
    set_status(heartbeat_t::RUNNING, run_.lockstep ? "lockstep" : "real time");
    log().info("starting at tick 0 ({})", run_.lockstep ? "lockstep" : "real time");
    wall_start_ = MonotonicSeconds();
    PublishState();
    if (run_.lockstep) StepWhileReady();
  }

  // The joint command the step from the current tick applies (< 0: none, initial targets).
  int64_t DueSeq() const { return tick_ - sim_params_.command_delay_ticks; }

  // Lockstep: steps for as long as the command each step needs has arrived (with a delay the
  // commands of the next ticks may already be in).
  void StepWhileReady() {
    while (started_ && !paused_ && !exit_requested()) {
      const int64_t due = DueSeq();
      if (due >= 0) {
        const auto it = commands_.find(due);
        if (it == commands_.end()) return;
        ApplyCommand(it->second);
        commands_.erase(it);  // the earliest: older ones are refused as stale
      } else if (tick_ == 0 && run_.resend_after_s > 0 && commands_.empty()) {
        // Tick 1 waits until tick 0 is answered: every node then starts its stream at tick 0,
        // and a lost first message is sent again rather than overtaken.
        return;
      }
      Advance();
    }
  }

  // Real time: applies, in order, every command that is due.
  void ApplyDueCommands() {
    while (!commands_.empty() && commands_.begin()->first <= DueSeq()) {
      ApplyCommand(commands_.begin()->second);
      commands_.erase(commands_.begin());
    }
  }

  void OnJointCmd(const lcm::ReceiveBuffer*, const std::string&, const joint_cmd_t* cmd) {
    if (!started_) return;
    if (run_.lockstep) {
      // Only the due command and those of ticks already published can be useful.
      if (cmd->seq < DueSeq() || cmd->seq > tick_ || commands_.count(cmd->seq) != 0) {
        ++stale_;
        return;
      }
      commands_.emplace(cmd->seq, *cmd);
      StepWhileReady();
    } else {
      if (cmd->seq < tick_ - 1) ++late_;
      // Sensor-to-command latency: from publishing tick k to receiving the command for it.
      if (cmd->seq >= 0 && cmd->seq <= tick_ && tick_ - cmd->seq < kLatencyWindow &&
          cmd->seq > last_answered_) {
        latencies_us_.push_back((MonotonicSeconds() - publish_times_[cmd->seq % kLatencyWindow]) *
                                1e6);
        last_answered_ = cmd->seq;
      }
      if (cmd->seq > tick_) {  // so at most command_delay_ticks commands wait
        ++rejected_;
        last_fault_ = "command for seq " + std::to_string(cmd->seq) + " ahead of tick " +
                      std::to_string(tick_);
        return;
      }
      commands_[cmd->seq] = *cmd;
      ApplyDueCommands();
    }
  }

  void ApplyCommand(const joint_cmd_t& cmd) {
    std::string why;
    bool ok = cmd.num_joints == model_.num_actuated() &&
              static_cast<int>(cmd.position.size()) == model_.num_actuated() &&
              static_cast<int>(cmd.name.size()) == model_.num_actuated();
    if (!ok) {
      why = "joint command with " + std::to_string(cmd.num_joints) + " joints, expected " +
            std::to_string(model_.num_actuated());
    } else {
      for (int i = 0; i < model_.num_actuated() && ok; ++i) {
        if (cmd.name[i] != sensors_msg_.joints.name[i]) {
          ok = false;
          why = "joint command names joint " + std::to_string(i) + " '" + cmd.name[i] +
                "', expected '" + sensors_msg_.joints.name[i] + "'";
        }
      }
      ok = ok && sim_.SetJointTargets(cmd.position, &why);
    }
    if (!ok) {
      ++rejected_;
      last_fault_ = "rejected command seq " + std::to_string(cmd.seq) + ": " + why;
      if (LogThisOccurrence(rejected_)) {
        log().warn("{} (rejected so far: {})", last_fault_, rejected_);
      }
      PublishStatus();
    }
    if (cmd.sim_command != 0) {
      // The supervisor's request, planned with this command (task_cmd_t.sim_command): it acts
      // now, before the step that applies the command, as a SIM_CONTROL of seq - 1 would.
      sim_control_t control{};
      control.seq = cmd.seq - 1;
      control.command = cmd.sim_command;
      control.reason = "the task's, with joint command " + std::to_string(cmd.seq);
      Apply(control);
    }
  }

  void ApplyControls() {
    while (!controls_.empty() && controls_.front().seq < DueSeq()) {
      Apply(controls_.front());
      controls_.pop_front();
    }
  }

  void Apply(const sim_control_t& c) {
    switch (c.command) {
      case sim_control_t::RELEASE:
        if (sim_.object_held()) log().info("object released at t = {:.3f} s", sim_.time());
        sim_.ReleaseObject();
        break;
      case sim_control_t::HOLD:
        sim_.HoldObject();
        break;
      case sim_control_t::RESET:
        sim_.Reset();
        log().info("reset to the initial scenario");
        break;
      case sim_control_t::PAUSE:
        // Said loudly: a pause from anything on the bus holds the whole run.
        if (!paused_) {
          log().warn("paused at t = {:.3f} s by a SIM_CONTROL ('{}'); the run waits for a RESUME",
                     sim_.time(), c.reason);
          paused_since_ = MonotonicSeconds();
        }
        paused_ = true;
        break;
      case sim_control_t::RESUME:
        if (paused_) {
          log().warn("resumed at t = {:.3f} s by a SIM_CONTROL ('{}') after {:.1f} s", sim_.time(),
                     c.reason, MonotonicSeconds() - paused_since_);
        }
        paused_ = false;
        break;
      case sim_control_t::STOP:
        log().info("stop requested ({}) at t = {:.3f} s", c.reason, sim_.time());
        Finish();
        break;
      default:
        log().warn("unknown sim control command {}", static_cast<int>(c.command));
    }
    PublishStatus();
  }

  void OnSimControl(const lcm::ReceiveBuffer*, const std::string&, const sim_control_t* c) {
    // Lockstep: a control carrying seq s (sent in answer to tick s) takes effect before the step
    // that applies the command of tick s + 1 (the step from s + 1 + delay): whoever sent it
    // answered tick s before anyone could answer tick s + 1, and it shares JOINT_CMD's bus, so
    // it is in first and lands at the same tick in every run, one process or many. Without a
    // seq (< 0) it applies at the next step.
    sim_control_t control = *c;
    if (control.seq < 0) control.seq = DueSeq() - 1;
    if (run_.lockstep && control.seq < DueSeq() - 1) {
      log().warn("late sim control for seq {} applied at tick {}", control.seq, tick_);
    }
    if (control.command == sim_control_t::RESUME || control.command == sim_control_t::PAUSE) {
      Apply(control);  // these act on the loop itself, now
      if (control.command == sim_control_t::RESUME && run_.lockstep) StepWhileReady();
      return;
    }
    controls_.push_back(control);
  }

  void Advance() {
    if (!run_.lockstep) ApplyDueCommands();
    ApplyControls();
    if (exit_requested()) return;  // a STOP
    const double t0 = MonotonicSeconds();
    for (int i = 0; i < sim_params_.steps_per_tick; ++i) sim_.Step();
    step_us_ = (MonotonicSeconds() - t0) * 1e6 / sim_params_.steps_per_tick;
    ++tick_;
    if (sim_.time() >= sim_params_.duration_s - 1e-9) {
      PublishState();
      log().info("reached the end of the run at t = {:.3f} s", sim_.time());
      Finish();
      return;
    }
    PublishState();
  }

  void Finish() {
    PublishStatus();
    const double wall = MonotonicSeconds() - wall_start_;
    if (!sim_params_.stats_file.empty()) WriteStats(wall);
    log().info("simulated {:.3f} s in {:.3f} s of wall time (real-time factor {:.2f}); faults {}, "
               "rejected commands {}, stale {}",
               sim_.time(), wall, wall > 0 ? sim_.time() / wall : 0.0, faults_, rejected_, stale_);
    RequestExit(faults_ >= run_.max_tick_faults ? kExitLockstepFault : 0);
  }

  void WriteStats(double wall) {
    auto percentile = [this](double p) {
      if (latencies_us_.empty()) return 0.0;
      std::vector<double> v = latencies_us_;
      const size_t i = std::min(v.size() - 1, static_cast<size_t>(p * v.size()));
      std::nth_element(v.begin(), v.begin() + i, v.end());
      return v[i];
    };
    std::ofstream out(sim_params_.stats_file);
    out << "{\"ticks\": " << tick_ << ", \"sim_time_s\": " << sim_.time()
        << ", \"wall_time_s\": " << wall << ", \"realtime_factor\": "
        << (wall > 0 ? sim_.time() / wall : 0.0) << ", \"tick_us\": "
        << (tick_ > 0 ? wall * 1e6 / tick_ : 0.0) << ", \"step_us_last\": " << step_us_
        << ", \"lockstep\": " << (run_.lockstep ? "true" : "false")
        << ", \"latency_samples\": " << latencies_us_.size()
        << ", \"latency_p50_us\": " << percentile(0.5)
        << ", \"latency_p99_us\": " << percentile(0.99) << ", \"late_commands\": " << late_
        << "}\n";
  }

  void CheckLockstep() {
    if (!started_) {
      if (MonotonicSeconds() - created_ > run_.tick_timeout_s * 10) {
        std::string missing;
        for (const auto& w : waiting_for_) missing += " " + w;
        log().error("lockstep participants never appeared:{}", missing);
        RequestExit(kExitLockstepFault);
      }
      return;
    }
    if (paused_ || exit_requested()) return;
    if (MonotonicSeconds() - published_at_ < run_.tick_timeout_s) return;
    ++faults_;
    last_fault_ = "lockstep fault: no JOINT_CMD for seq " + std::to_string(DueSeq()) + " within " +
                  std::to_string(run_.tick_timeout_s) + " s";
    log().error("{} (fault {}/{})", last_fault_, faults_, run_.max_tick_faults);
    PublishStatus();
    published_at_ = MonotonicSeconds();
    if (faults_ >= run_.max_tick_faults) {
      log().error("giving up after {} lockstep faults", faults_);
      Finish();
    }
  }

  // --- real time ----------------------------------------------------------------------------
  void RealTimeStep() {
    if (!started_ || paused_ || exit_requested()) return;
    const double due = (MonotonicSeconds() - wall_start_) * sim_params_.realtime_rate;
    // Catch up, but never more than a few steps at once (no spiral of death).
    for (int i = 0; i < 5 && sim_.time() + TickSeconds() <= due + 1e-9; ++i) {
      Advance();
      if (exit_requested()) return;
    }
  }

  void ReportProgress() {
    if (!started_) return;
    if (paused_) {
      const double paused_s = MonotonicSeconds() - paused_since_;
      set_status(heartbeat_t::RUNNING, "paused for " + std::to_string(paused_s) + " s");
      if (paused_s > 2.0 && std::fmod(paused_s, 30.0) < 2.0) {  // every half minute
        log().warn("still paused at t = {:.3f} s ({:.0f} s): waiting for a RESUME", sim_.time(),
                   paused_s);
      }
      return;
    }
    set_status(heartbeat_t::RUNNING, "t = " + std::to_string(sim_.time()) + " s");
  }

  RunParams run_;
  RateGate view_gate_;  // DMPL_VIEW_TRUTH
  SimParams sim_params_;
  HandModel model_;
  HandSim sim_;
  hand_sensors_t sensors_msg_{};
  std::vector<std::string> waiting_for_;
  std::deque<sim_control_t> controls_;
  std::map<int64_t, joint_cmd_t> commands_;  // by seq, not yet applied
  bool started_ = false;
  bool paused_ = false;
  double paused_since_ = 0;
  int64_t tick_ = 0;
  int faults_ = 0;
  int rejected_ = 0;
  int late_ = 0;
  int64_t stale_ = 0;
  double step_us_ = 0;
  std::string last_fault_;
  double created_ = MonotonicSeconds();
  static constexpr int64_t kLatencyWindow = 1024;
  std::vector<double> publish_times_ = std::vector<double>(kLatencyWindow, 0.0);
  std::vector<double> latencies_us_;
  int64_t last_answered_ = -1;
  double published_at_ = 0;
  double wall_start_ = 0;
};

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeSimNode(const NodeContext& ctx) {
  HandParams hand;
  SimParams sim;
  ObjectParams object;
  ctx.config.Load("hand", &hand);
  ctx.config.Load("sim", &sim);
  ctx.config.Load("object", &object);
  sim.Validate(ctx.config.source());
  object.Validate(ctx.config.source());
  return std::make_unique<SimNode>(ctx, HandModel::Load(hand), sim, object);
}

const NodeInfo kSimNode = {"dmpl_sim", "run, hand, sim, object", MakeSimNode};

}  // namespace dmpl
