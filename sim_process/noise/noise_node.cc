// dmpl_noise: DMPL_SENSORS_TRUE in, DMPL_SENSORS out (and DMPL_VIEW_SENSED at run.view_rate_hz
// for viewers; README, "The processes"). Reads sections
// `run`, `noise`.
#include "components/runtime/channels.h"
#include "components/runtime/lockstep.h"
#include "components/runtime/node.h"
#include "sim_process/noise/noise_node.h"
#include "dmpl/heartbeat_t.hpp"
#include "sim_process/noise/noise_injector.h"
#include "sim_process/noise/sensors_translation.h"

namespace dmpl {
namespace {

class NoiseNode : public Node {
 public:
  NoiseNode(const NodeContext& ctx, const NoiseParams& params)
      : Node(ctx),
        lockstep_(ctx.run.lockstep),
        injector_(params, ctx.run.seed),
        view_gate_(ctx.run.view_rate_hz) {
    KeepForResend(ctx.run, 4);
    Subscribe(channels::kSensorsTrue, &NoiseNode::OnSensors, this);
    AddTimer(1.0, [this] { ReportRejections(); });
  }

 private:
  void OnSensors(const lcm::ReceiveBuffer*, const std::string&, const hand_sensors_t* truth) {
    if (!lockstep_) {
      Sense(*truth);
      return;
    }
    // The injector has state (delays, drifts): each tick once, in order.
    using Verdict = InOrder<hand_sensors_t>::Verdict;
    if (in_order_.Arrive(truth->seq, *truth, &ready_) == Verdict::kTooFarAhead) {
      log().warn("truth of tick {} far ahead of tick {}: not adopted", truth->seq,
                 in_order_.next());
    }
    for (const hand_sensors_t& t : ready_) Sense(t);
  }

  void Sense(const hand_sensors_t& truth) {
    std::string why;
    const std::optional<HandReading> reading = ToReading(truth, &why);
    if (!reading) {
      injector_.Reject(why);
      return;
    }
    if (const std::optional<HandReading> sensed = injector_.Sense(*reading)) {
      hand_sensors_t m = ToMessage(*sensed);
      m.run_id = run_id();
      PublishLoop(channels::kSensors, m);
      if (view_gate_.Due(m.utime)) Publish(channels::kViewSensed, m);
      set_tick(truth.seq);
    }
  }
  void ReportRejections() {
    if (injector_.rejected() == reported_) return;
    reported_ = injector_.rejected();
    log().warn("rejected {} malformed truth messages so far (last: {})", reported_,
               injector_.last_rejection());
    set_status(heartbeat_t::RUNNING, "rejected " + std::to_string(reported_) + ": " +
                                         injector_.last_rejection());
  }

  bool lockstep_;
  InOrder<hand_sensors_t> in_order_;
  std::vector<hand_sensors_t> ready_;
  NoiseInjector injector_;
  RateGate view_gate_;  // DMPL_VIEW_SENSED
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

const NodeInfo kNoiseNode = {"dmpl_noise", "run, noise", MakeNoiseNode};

}  // namespace dmpl
