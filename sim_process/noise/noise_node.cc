// dmpl_noise: ground truth in, sensed channels out (DESIGN.md §1). Reads sections `run`, `noise`.
#include "components/runtime/channels.h"
#include "components/runtime/node.h"
#include "components/runtime/node_factories.h"
#include "dmpl/heartbeat_t.hpp"
#include "sim_process/noise/noise_injector.h"

namespace dmpl {
namespace {

class NoiseNode : public Node {
 public:
  NoiseNode(const NodeContext& ctx, const NoiseParams& params)
      : Node(ctx.name, ctx.bus), injector_(params, ctx.run.seed) {
    listen(channels::kHandStateTrue).subscribe(channels::kHandStateTrue, &NoiseNode::OnJoints, this);
    listen(channels::kObjectPoseTrue).subscribe(channels::kObjectPoseTrue, &NoiseNode::OnObject, this);
    listen(channels::kTactileTrue).subscribe(channels::kTactileTrue, &NoiseNode::OnTactile, this);
    AddTimer(1.0, [this] { ReportRejections(); });
  }

 private:
  template <typename Msg>
  void Forward(const char* channel, const Msg& truth) {
    if (auto sensed = injector_.Sense(truth)) {
      lcm(channel).publish(channel, &*sensed);
      set_tick(truth.seq);
    }
  }
  void OnJoints(const lcm::ReceiveBuffer*, const std::string&, const joint_state_t* m) {
    Forward(channels::kHandState, *m);
  }
  void OnObject(const lcm::ReceiveBuffer*, const std::string&, const object_pose_t* m) {
    Forward(channels::kObjectPose, *m);
  }
  void OnTactile(const lcm::ReceiveBuffer*, const std::string&, const tactile_t* m) {
    Forward(channels::kTactile, *m);
  }
  void ReportRejections() {
    if (injector_.rejected() == reported_) return;
    reported_ = injector_.rejected();
    log().warn("rejected {} malformed truth messages so far (last: {})", reported_,
               injector_.last_rejection());
    set_status(heartbeat_t::RUNNING, "rejected " + std::to_string(reported_) + ": " +
                                         injector_.last_rejection());
  }

  NoiseInjector injector_;
  int64_t reported_ = 0;
};

}  // namespace
}  // namespace dmpl

namespace dmpl {

std::unique_ptr<Node> MakeNoiseNode(const NodeContext& ctx) {
  NoiseParams params;
  ctx.config.Load("noise", &params);
  params.Validate(ctx.config.source());
  return std::make_unique<NoiseNode>(ctx, params);
}

}  // namespace dmpl

#ifndef DMPL_NO_MAIN
int main(int argc, char** argv) {
  return dmpl::RunNodeMain(argc, argv, "dmpl_noise", "Reads sections: run, noise.",
                           dmpl::MakeNoiseNode);
}
#endif
