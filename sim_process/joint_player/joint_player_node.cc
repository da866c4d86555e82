// dmpl_joint_player: plays a joint-space trajectory (section joint_player) onto DMPL_JOINT_CMD,
// answering each sensed tick (DMPL_SENSORS) in lockstep. Reads sections: run, hand, joint_player.
#include "components/runtime/channels.h"
#include "components/runtime/node.h"
#include "sim_process/joint_player/joint_player_node.h"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/joint_cmd_t.hpp"
#include "dmpl/sim_control_t.hpp"
#include "sim_process/joint_player/joint_trajectory.h"

namespace dmpl {
namespace {

class JointPlayerNode : public Node {
 public:
  JointPlayerNode(const NodeContext& ctx, const HandModel& model, const JointPlayerParams& params)
      : Node(ctx),
        params_(params),
        trajectory_(model, params.waypoints, ctx.config.source()) {
    cmd_.run_id = run_id();
    cmd_.name = model.actuated_names();
    cmd_.num_joints = static_cast<int16_t>(cmd_.name.size());
    Subscribe(channels::kSensors, &JointPlayerNode::OnSensors, this);
  }

 private:
  void OnSensors(const lcm::ReceiveBuffer*, const std::string&, const hand_sensors_t* m) {
    if (m->seq <= last_seq_) return;  // every tick answered once
    last_seq_ = m->seq;
    set_tick(m->seq);
    const double t = m->utime * 1e-6;
    if (params_.release_at_s >= 0 && !released_ && t >= params_.release_at_s) {
      SendControl(sim_control_t::RELEASE, m->seq, "joint_player.release_at_s");
      released_ = true;
    }
    if (params_.stop_at_s >= 0 && !stopped_ && t >= params_.stop_at_s) {
      SendControl(sim_control_t::STOP, m->seq, "joint_player.stop_at_s");
      stopped_ = true;
    }
    cmd_.utime = m->utime;
    cmd_.seq = m->seq;
    cmd_.position = trajectory_.At(t);
    Publish(channels::kJointCmd, cmd_);
  }

  void SendControl(int8_t command, int64_t seq, const std::string& reason) {
    sim_control_t c{};
    c.run_id = run_id();
    c.seq = seq;
    c.command = command;
    c.reason = reason;
    Publish(channels::kSimControl, c);
  }

  JointPlayerParams params_;
  JointTrajectory trajectory_;
  joint_cmd_t cmd_{};
  int64_t last_seq_ = -1;
  bool released_ = false;
  bool stopped_ = false;
};

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeJointPlayerNode(const NodeContext& ctx) {
  HandParams hand;
  JointPlayerParams params;
  ctx.config.Load("hand", &hand);
  ctx.config.Load("joint_player", &params);
  static const HandModel model = HandModel::Load(hand);
  return std::make_unique<JointPlayerNode>(ctx, model, params);
}

const NodeInfo kJointPlayerNode = {"dmpl_joint_player", "run, hand, joint_player", MakeJointPlayerNode};

}  // namespace dmpl
