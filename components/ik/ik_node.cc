// dmpl_ik: Cartesian fingertip targets (DMPL_FINGER_TARGETS) -> joint command (DMPL_JOINT_CMD).
// The targets carry the sensed joints they were planned from; the solve starts there. Each
// targets message is answered once (lockstep: the command for tick k answers the targets of k).
// Reads sections: run, hand, ik.
#include <cmath>

#include "components/ik/hand_ik.h"
#include "components/runtime/channels.h"
#include "components/runtime/clock.h"
#include "components/runtime/lcm_eigen.h"
#include "components/runtime/lockstep.h"
#include "components/runtime/node.h"
#include "components/ik/ik_node.h"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/heartbeat_t.hpp"
#include "dmpl/ik_status_t.hpp"
#include "dmpl/joint_cmd_t.hpp"

namespace dmpl {
namespace {

class IkNode : public Node {
 public:
  IkNode(const NodeContext& ctx, HandModel model, const IkParams& params)
      : Node(ctx),
        lockstep_(ctx.run.lockstep),
        model_(std::move(model)),
        kin_(model_),
        ik_(kin_, params) {
    cmd_.run_id = run_id();
    cmd_.name = model_.actuated_names();
    cmd_.num_joints = static_cast<int16_t>(cmd_.name.size());
    status_.num_fingers = static_cast<int8_t>(kin_.num_fingers());
    status_.fingers.resize(kin_.num_fingers());
    for (int f = 0; f < kin_.num_fingers(); ++f) status_.fingers[f].finger = kin_.finger(f).name();
    last_status_.assign(kin_.num_fingers(), -1);
    KeepForResend(ctx.run, 4);
    Subscribe(channels::kFingerTargets, &IkNode::OnTargets, this);
  }

 private:
  void OnTargets(const lcm::ReceiveBuffer*, const std::string&, const finger_targets_t* m) {
    if (m->num_joints != kin_.num_joints() ||
        static_cast<int>(m->joint_position.size()) != m->num_joints) {
      Reject("targets planned from " + std::to_string(m->num_joints) + " joints");
      return;
    }
    for (double q : m->joint_position) {
      if (!std::isfinite(q)) {
        Reject("targets planned from joints with NaN");
        return;
      }
    }
    if (std::string out = kin_.OutOfLimits(m->joint_position, InputBounds::kJointMarginRad);
        !out.empty()) {
      Reject("targets planned from joints beyond the hand's limits: " + out);
      return;
    }
    for (const auto& t : m->fingers) {
      const Eigen::Vector3d p = ToVector3(t.position);
      if (t.mode == finger_target_t::POSITION && p.allFinite() &&
          p.norm() > InputBounds::kWorkspaceRadiusM) {
        Reject("target for finger " + t.finger + " " + std::to_string(p.norm()) +
               " m from the palm, outside the hand's workspace");
        return;
      }
    }
    if (!lockstep_) {
      targets_ = *m;
      Solve(m->seq);
      return;
    }
    // Every tick answered once, in order (a lost one is sent again; those after it wait).
    using Verdict = InOrder<finger_targets_t>::Verdict;
    if (in_order_.Arrive(m->seq, *m, &ready_) == Verdict::kTooFarAhead) {
      Reject("targets for tick " + std::to_string(m->seq) + ", far ahead of tick " +
             std::to_string(in_order_.next()) + ": not adopted");
    }
    for (finger_targets_t& t : ready_) {
      targets_ = std::move(t);
      Solve(targets_.seq);
    }
  }

  void Reject(const std::string& why) {
    ++rejected_;
    if (LogThisOccurrence(rejected_)) log().warn("rejected input: {} ({} so far)", why, rejected_);
    set_status(heartbeat_t::RUNNING, "rejected " + std::to_string(rejected_) + ": " + why);
  }

  void Solve(int64_t tick) {
    const double t0 = MonotonicSeconds();
    std::vector<std::optional<Eigen::Vector3d>> targets(kin_.num_fingers());
    std::vector<Eigen::Vector3d> approaches(kin_.num_fingers(), Eigen::Vector3d::Zero());
    for (const auto& t : targets_.fingers) {
      const int f = kin_.FindFinger(t.finger);
      if (f < 0) {
        Reject("target for unknown finger '" + t.finger + "'");
        continue;
      }
      if (t.mode == finger_target_t::POSITION) {
        targets[f] = ToVector3(t.position);
        const Eigen::Vector3d approach = ToVector3(t.approach);
        const double norm = approach.norm();
        if (std::isfinite(norm) && norm > 0.5 && norm < 1.5) approaches[f] = approach / norm;
      }
    }
    const std::vector<double>& q = ik_.Step(targets_.joint_position, targets, approaches);
    cmd_.utime = targets_.utime;
    cmd_.seq = tick;
    cmd_.sim_command = targets_.sim_command;
    cmd_.position = q;
    status_.utime = targets_.utime;
    status_.seq = tick;
    status_.solve_us = (MonotonicSeconds() - t0) * 1e6;
    for (int f = 0; f < kin_.num_fingers(); ++f) {
      const FingerIkReport& r = ik_.reports()[f];
      status_.fingers[f].status = static_cast<int8_t>(r.status);
      status_.fingers[f].residual_m = r.residual_m;
      status_.fingers[f].iterations = static_cast<int16_t>(r.iterations);
      if (r.status == IkStatus::kRejected) Reject("NaN target for finger " + kin_.finger(f).name());
    }
    // The status at 100 Hz and whenever a finger's status changes, on the monitor bus (for
    // people and tools; no process of the loop wakes for it).
    bool changed = false;
    for (int f = 0; f < kin_.num_fingers(); ++f) {
      changed = changed || status_.fingers[f].status != last_status_[f];
      last_status_[f] = status_.fingers[f].status;
    }
    if (changed || tick % 10 == 0) PublishRecorded(channels::kIkStatus, status_);
    PublishLoop(channels::kJointCmd, cmd_);
    set_tick(tick);
  }

  bool lockstep_;
  HandModel model_;
  HandKinematics kin_;
  HandIk ik_;
  finger_targets_t targets_{};
  InOrder<finger_targets_t> in_order_;
  std::vector<finger_targets_t> ready_;
  joint_cmd_t cmd_{};
  ik_status_t status_{};
  std::vector<int8_t> last_status_;  // per finger: the status last published
  int64_t rejected_ = 0;
};

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeIkNode(const NodeContext& ctx) {
  HandParams hand;
  IkParams ik;
  ctx.config.Load("hand", &hand);
  ctx.config.Load("ik", &ik);
  ik.Validate(ctx.config.source());
  return std::make_unique<IkNode>(ctx, HandModel::Load(hand), ik);
}

const NodeInfo kIkNode = {"dmpl_ik", "run, hand, ik", MakeIkNode};

}  // namespace dmpl
