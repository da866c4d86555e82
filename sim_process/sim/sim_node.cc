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
#include <fstream>
#include <memory>

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
#include "sim_process/sim/background_step.h"
#include "sim_process/sim/hand_sim.h"
#include "sim_process/sim/sim_scheduler.h"

namespace dmpl {
namespace {

constexpr int kExitLockstepFault = 4;

class SimNode : public Node, private SimLoop {
 public:
  SimNode(const NodeContext& ctx, HandModel model, const SimParams& sim, const ObjectParams& object)
      : Node(ctx),
        run_(ctx.run),
        view_gate_(ctx.run.view_rate_hz),
        sim_params_(sim),
        model_(std::move(model)),
        sim_(model_, sim, object, ctx.config.source()),  // validates sim and object
        scheduler_(ScheduleParams(ctx.run, sim), this) {
    Subscribe(channels::kJointCmd, &SimNode::OnJointCmd, this);
    Subscribe(channels::kSimControl, &SimNode::OnSimControl, this);
    Subscribe(channels::kHeartbeat, &SimNode::OnHeartbeat, this);
    for (const auto& p : run_.lockstep_participants) waiting_for_.push_back(p);
    KeepForResend(run_, 4);  // the truths of the ticks that may still be unanswered
    PrepareMessages();
    if (sim.background_step && run_.lockstep && sim.command_delay_ticks >= 1 &&
        ctx.bus->in_process() != nullptr && BackgroundStep::Parallel()) {
      stepper_ = std::make_unique<BackgroundStep>();
    }
    if (run_.lockstep) {
      AddTimer(0.05, [this] { CheckLockstep(); });
    } else {
      AddTimer(sim_params_.physics.time_step / sim_params_.realtime_rate, [this] { RealTimeStep(); });
    }
    AddTimer(2.0, [this] { ReportProgress(); });
  }

  void OnStart() override {
    set_status(heartbeat_t::STARTING, "waiting for lockstep participants");
    if (!run_.lockstep || waiting_for_.empty()) Begin();
  }

 private:
  static SimScheduleParams ScheduleParams(const RunParams& run, const SimParams& sim) {
    SimScheduleParams p;
    p.lockstep = run.lockstep;
    p.command_delay_ticks = sim.command_delay_ticks;
    p.first_tick_waits = run.resend_after_s > 0;
    p.tick_timeout_s = run.tick_timeout_s;
    p.max_tick_faults = run.max_tick_faults;
    return p;
  }

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
  void PublishTick(int64_t tick) override {
    const int64_t utime = std::llround(sim_.time() * 1e6);
    sensors_msg_.utime = utime;
    sensors_msg_.seq = tick;
    const JointState j = sim_.joints();
    joint_state_t& joints = sensors_msg_.joints;
    joints.utime = utime;
    joints.seq = tick;
    joints.position = j.position;
    joints.velocity = j.velocity;
    joints.effort = j.effort;

    const ObjectState o = sim_.object();
    object_pose_t& pose = sensors_msg_.object;
    pose.utime = utime;
    pose.seq = tick;
    pose.valid = true;
    ToArray(Eigen::Vector3d(o.pose.translation()), pose.position);
    ToArray(Eigen::Quaterniond(o.pose.linear()), pose.orientation);
    ToArray(o.linear_velocity, pose.linear_velocity);
    ToArray(o.angular_velocity, pose.angular_velocity);

    tactile_t& tactile = sensors_msg_.tactile;
    tactile.utime = utime;
    tactile.seq = tick;
    const auto& tips = sim_.tactile();
    for (size_t f = 0; f < tips.size(); ++f) {
      fingertip_contact_t& c = tactile.fingers[f];
      c.in_contact = tips[f].in_contact;
      c.force_n = tips[f].force;
      c.num_points = static_cast<int16_t>(tips[f].points);
      c.link_force_n = tips[f].link_force;
      for (int i = 0; i < 3; ++i) {
        c.position[i] = tips[f].position[i];
        c.normal[i] = tips[f].normal[i];
      }
    }
    ToArray(sim_.gravity_in_palm(), sensors_msg_.gravity);
    PublishLoop(channels::kSensorsTrue, sensors_msg_);
    if (view_gate_.Due(utime)) {
      Publish(channels::kViewTruth, sensors_msg_);
    }
    if (!run_.lockstep) publish_times_[tick % kLatencyWindow] = MonotonicSeconds();
    set_tick(tick);
    // Status at 10 Hz of simulated time, and whenever something went wrong.
    if (tick % std::max<int64_t>(1, std::llround(0.1 / TickSeconds())) == 0) PublishStatus();
  }

  void PublishStatus() {
    sim_status_t s{};
    s.utime = std::llround(sim_.time() * 1e6);
    s.seq = scheduler_.tick();
    s.sim_time_s = sim_.time();
    s.lockstep = run_.lockstep;
    s.paused = scheduler_.paused();
    s.object_held = sim_.object_held();
    s.steps = sim_.steps();
    s.faults = scheduler_.faults();
    s.rejected_commands = rejected_;
    s.late_commands = late_;
    s.step_us = step_us_;
    s.last_fault = last_fault_;
    PublishRecorded(channels::kSimStatus, s);
  }

  double TickSeconds() const { return sim_params_.physics.time_step * sim_params_.steps_per_tick; }

  static JointCommand FromMessage(const joint_cmd_t& m) {
    JointCommand c;
    c.seq = m.seq;
    c.names = m.name;
    c.positions = m.position;
    c.request = static_cast<SimRequest>(m.sim_command);
    return c;
  }

  static SimControl FromMessage(const sim_control_t& m) {
    return SimControl{m.seq, static_cast<SimRequest>(m.command), m.reason};
  }

  // --- lockstep -----------------------------------------------------------------------------
  void OnHeartbeat(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* hb) {
    if (scheduler_.started()) return;
    for (auto it = waiting_for_.begin(); it != waiting_for_.end(); ++it) {
      if (*it == hb->process) {
        waiting_for_.erase(it);
        break;
      }
    }
    if (waiting_for_.empty()) Begin();
  }

  void Begin() {
    if (scheduler_.started()) return;
    set_status(heartbeat_t::RUNNING, run_.lockstep ? "lockstep" : "real time");
    log().info("starting at tick 0 ({})", run_.lockstep ? "lockstep" : "real time");
    wall_start_ = MonotonicSeconds();
    scheduler_.Begin(wall_start_);
  }

  void OnJointCmd(const lcm::ReceiveBuffer*, const std::string&, const joint_cmd_t* cmd) {
    FinishStep();
    if (!scheduler_.started() || exit_requested()) return;
    const double now = MonotonicSeconds();
    if (!run_.lockstep) MeasureLatency(*cmd, now);
    if (scheduler_.OnCommand(FromMessage(*cmd), now) == SimScheduler::Verdict::kAhead) {
      ++rejected_;
      last_fault_ = "command for seq " + std::to_string(cmd->seq) + " ahead of tick " +
                    std::to_string(scheduler_.tick());
    }
  }

  // Real time: late commands, and the latency from publishing tick k to receiving its answer.
  void MeasureLatency(const joint_cmd_t& cmd, double now) {
    const int64_t tick = scheduler_.tick();
    if (cmd.seq < tick - 1) ++late_;
    if (cmd.seq >= 0 && cmd.seq <= tick && tick - cmd.seq < kLatencyWindow &&
        cmd.seq > last_answered_) {
      latencies_us_.push_back((now - publish_times_[cmd.seq % kLatencyWindow]) * 1e6);
      last_answered_ = cmd.seq;
    }
  }

  void ApplyCommand(const JointCommand& cmd) override {
    std::string why;
    bool ok = static_cast<int>(cmd.positions.size()) == model_.num_actuated() &&
              static_cast<int>(cmd.names.size()) == model_.num_actuated();
    if (!ok) {
      why = "joint command with " + std::to_string(cmd.positions.size()) +
            " joints, expected " + std::to_string(model_.num_actuated());
    } else {
      for (int i = 0; i < model_.num_actuated() && ok; ++i) {
        if (cmd.names[i] != sensors_msg_.joints.name[i]) {
          ok = false;
          why = "joint command names joint " + std::to_string(i) + " '" + cmd.names[i] +
                "', expected '" + sensors_msg_.joints.name[i] + "'";
        }
      }
      ok = ok && sim_.SetJointTargets(cmd.positions, &why);
    }
    if (!ok) {
      ++rejected_;
      last_fault_ = "rejected command seq " + std::to_string(cmd.seq) + ": " + why;
      if (LogThisOccurrence(rejected_)) {
        log().warn("{} (rejected so far: {})", last_fault_, rejected_);
      }
      PublishStatus();
    }
  }

  void ApplyControl(const SimControl& c) override {
    switch (c.command) {
      case SimRequest::kRelease:
        if (sim_.object_held()) log().info("object released at t = {:.3f} s", sim_.time());
        sim_.ReleaseObject();
        break;
      case SimRequest::kHold:
        sim_.HoldObject();
        break;
      case SimRequest::kReset:
        sim_.Reset();
        log().info("reset to the initial scenario");
        break;
      default:
        log().warn("unknown sim control command {}", static_cast<int>(c.command));
    }
    PublishStatus();
  }

  void Paused(const SimControl& c) override {
    // Said loudly: a pause from anything on the bus holds the whole run.
    log().warn("paused at t = {:.3f} s by a SIM_CONTROL ('{}'); the run waits for a RESUME",
               sim_.time(), c.reason);
    PublishStatus();
  }

  void Resumed(const SimControl& c, double paused_for_s) override {
    log().warn("resumed at t = {:.3f} s by a SIM_CONTROL ('{}') after {:.1f} s", sim_.time(),
               c.reason, paused_for_s);
    PublishStatus();
  }

  void OnSimControl(const lcm::ReceiveBuffer*, const std::string&, const sim_control_t* c) {
    FinishStep();
    const int64_t tick = scheduler_.tick();
    if (!scheduler_.OnControl(FromMessage(*c), MonotonicSeconds())) {
      log().warn("late sim control for seq {} applied at tick {}", c->seq, tick);
    }
  }

  bool StepTo(int64_t tick) override {
    FinishStep();
    // The time the step ends at, as the simulator sums it.
    double end = sim_.time();
    for (int i = 0; i < sim_params_.steps_per_tick; ++i) end += sim_params_.physics.time_step;
    const bool last = end >= sim_params_.duration_s - 1e-9;
    if (stepper_ != nullptr && !last) {
      // Its truth goes out when something next needs the simulator (FinishStep): in lockstep,
      // the command that answers the tick before, which the nodes compute meanwhile.
      stepped_tick_ = tick;
      stepper_->Start([this] { Step(); });
      return false;
    }
    Step();
    PublishTick(tick);
    if (!last) return false;
    log().info("reached the end of the run at t = {:.3f} s", sim_.time());
    return true;
  }

  void Step() {
    const double t0 = MonotonicSeconds();
    for (int i = 0; i < sim_params_.steps_per_tick; ++i) sim_.Step();
    step_us_ = (MonotonicSeconds() - t0) * 1e6 / sim_params_.steps_per_tick;
  }

  // Waits for a step under way in the background and publishes its truth: before anything
  // reads or changes the simulator.
  void FinishStep() {
    if (stepped_tick_ < 0) return;
    const int64_t tick = stepped_tick_;
    stepped_tick_ = -1;  // a step that threw is not published
    stepper_->Wait();
    PublishTick(tick);
  }

  void Fault(const std::string& what) override {
    last_fault_ = what;
    log().error("{} (fault {}/{})", what, scheduler_.faults(), run_.max_tick_faults);
    PublishStatus();
  }

  void Finished(const SimControl* stop, bool gave_up) override {
    FinishStep();
    if (stop != nullptr) {
      log().info("stop requested ({}) at t = {:.3f} s", stop->reason, sim_.time());
    }
    if (gave_up) log().error("giving up after {} lockstep faults", scheduler_.faults());
    PublishStatus();
    const double wall = MonotonicSeconds() - wall_start_;
    if (!sim_params_.stats_file.empty()) WriteStats(wall);
    log().info("simulated {:.3f} s in {:.3f} s of wall time (real-time factor {:.2f}); faults {}, "
               "rejected commands {}, stale {}",
               sim_.time(), wall, wall > 0 ? sim_.time() / wall : 0.0, scheduler_.faults(),
               rejected_, scheduler_.stale());
    RequestExit(gave_up ? kExitLockstepFault : 0);
  }

  void WriteStats(double wall) {
    auto percentile = [this](double p) {
      if (latencies_us_.empty()) return 0.0;
      std::vector<double> v = latencies_us_;
      const size_t i = std::min(v.size() - 1, static_cast<size_t>(p * v.size()));
      std::nth_element(v.begin(), v.begin() + i, v.end());
      return v[i];
    };
    const int64_t ticks = scheduler_.tick();
    std::ofstream out(sim_params_.stats_file);
    out << "{\"ticks\": " << ticks << ", \"sim_time_s\": " << sim_.time()
        << ", \"wall_time_s\": " << wall << ", \"realtime_factor\": "
        << (wall > 0 ? sim_.time() / wall : 0.0) << ", \"tick_us\": "
        << (ticks > 0 ? wall * 1e6 / ticks : 0.0) << ", \"step_us_last\": " << step_us_
        << ", \"lockstep\": " << (run_.lockstep ? "true" : "false")
        << ", \"latency_samples\": " << latencies_us_.size()
        << ", \"latency_p50_us\": " << percentile(0.5)
        << ", \"latency_p99_us\": " << percentile(0.99) << ", \"late_commands\": " << late_
        << "}\n";
  }

  void CheckLockstep() {
    FinishStep();
    if (scheduler_.started()) {
      if (!exit_requested()) scheduler_.CheckTimeout(MonotonicSeconds());
      return;
    }
    if (MonotonicSeconds() - created_ > run_.tick_timeout_s * 10) {
      std::string missing;
      for (const auto& w : waiting_for_) missing += " " + w;
      log().error("lockstep participants never appeared:{}", missing);
      RequestExit(kExitLockstepFault);
    }
  }

  // --- real time ----------------------------------------------------------------------------
  void RealTimeStep() {
    FinishStep();
    if (exit_requested()) return;
    const double now = MonotonicSeconds();
    const double due = (now - wall_start_) * sim_params_.realtime_rate;
    // Catch up, but never more than a few steps at once (no spiral of death).
    for (int i = 0; i < 5 && sim_.time() + TickSeconds() <= due + 1e-9; ++i) {
      if (!scheduler_.AdvanceRealTime(now)) return;
    }
  }

  void ReportProgress() {
    FinishStep();
    if (!scheduler_.started()) return;
    if (scheduler_.paused()) {
      const double paused_s = MonotonicSeconds() - scheduler_.paused_since();
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
  SimScheduler scheduler_;
  hand_sensors_t sensors_msg_{};
  std::vector<std::string> waiting_for_;
  int rejected_ = 0;
  int late_ = 0;
  double step_us_ = 0;
  std::string last_fault_;
  double created_ = MonotonicSeconds();
  static constexpr int64_t kLatencyWindow = 1024;
  std::vector<double> publish_times_ = std::vector<double>(kLatencyWindow, 0.0);
  std::vector<double> latencies_us_;
  int64_t last_answered_ = -1;
  double wall_start_ = 0;
  // sim.background_step: the step under way on its own thread, and the tick it steps to (-1:
  // none). Last: it goes first, its step done, before what the step touches.
  int64_t stepped_tick_ = -1;
  std::unique_ptr<BackgroundStep> stepper_;
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
  auto node = std::make_unique<SimNode>(ctx, HandModel::Load(hand), sim, object);
  // Every node takes the loop's period from run.tick_s: it must be this simulator's tick.
  const double tick_s = sim.physics.time_step * sim.steps_per_tick;
  if (std::abs(ctx.run.tick_s - tick_s) > 1e-9 * tick_s) {
    throw ConfigError("config error in " + ctx.config.source() + ": key 'run.tick_s': " +
                      std::to_string(ctx.run.tick_s) + " s, but the simulator's tick " +
                      "(sim.physics.time_step x sim.steps_per_tick) is " +
                      std::to_string(tick_s) + " s");
  }
  return node;
}

const NodeInfo kSimNode = {"dmpl_sim", "run, hand, sim, object", MakeSimNode};

}  // namespace dmpl
