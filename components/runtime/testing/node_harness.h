#pragma once
// One node on a memq:// bus of its own, driven message by message by a gtest: the node's
// protocol (what it answers, in which order, what it refuses) without processes or sockets.
//
//   NodeHarness h(kIkNode, {"run.lockstep=true"});
//   auto& commands = h.Collect<joint_cmd_t>(channels::kJointCmd);
//   h.Publish(channels::kFingerTargets, targets);   // delivered, answers collected
//   EXPECT_EQ(commands.back().seq, targets.seq);
#include <cstdlib>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "components/logging/decode.h"
#include "components/runtime/config.h"
#include "components/runtime/node.h"

namespace dmpl::testing {

class NodeHarness {
 public:
  // `sets`: --set overrides of the node's config (relative paths from the source tree).
  NodeHarness(const NodeInfo& info, const std::vector<std::string>& sets)
      : bus_("memq://", false) {
    ::setenv("DMPL_ROOT", DMPL_SOURCE_DIR, 0);
    ctx_.name = info.name;
    ctx_.config = Config::Resolve("", {}, sets);
    ctx_.config.Load("run", &ctx_.run);
    ctx_.run.Validate(ctx_.config.source());
    ctx_.bus = &bus_;
    node_ = info.make(ctx_);
    node_->OnStart();
  }

  // Collects every message the node publishes on `channel` (call before publishing).
  template <typename Msg>
  std::deque<Msg>& Collect(const std::string& channel) {
    auto sink = std::make_unique<Sink<Msg>>();
    std::deque<Msg>& messages = sink->messages;
    Sink<Msg>* s = sink.get();
    bus_.Subscribe(channel, [s](const lcm::ReceiveBuffer* rbuf, const std::string& ch) {
      s->OnMessage(rbuf, ch);
    });
    sinks_.push_back(std::move(sink));
    return messages;
  }

  // Publishes `msg` as any process would, and delivers it and whatever it causes.
  template <typename Msg>
  void Publish(const std::string& channel, const Msg& msg) {
    bus_.Publish(channel, msg);
    Deliver();
  }
  // Bytes that are not a message of the channel's type.
  void PublishBytes(const std::string& channel, const std::string& bytes) {
    bus_.Publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
    Deliver();
  }

  Node& node() { return *node_; }

 private:
  struct SinkBase {
    virtual ~SinkBase() = default;
  };
  template <typename Msg>
  struct Sink : SinkBase {
    std::deque<Msg> messages;
    void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      Msg m;
      if (!DecodeMessage(rbuf->data, rbuf->data_size, &m)) {
        ADD_FAILURE() << "the node published a message on " << channel << " that is not a "
                      << Msg::getTypeName();
        return;
      }
      messages.push_back(std::move(m));
    }
  };

  // The in-process queue hands messages over one at a time: until nothing is left.
  void Deliver() {
    for (int i = 0; i < 10000; ++i) {
      if (!bus_.in_process()->DeliverOne()) return;
    }
    ADD_FAILURE() << "the node keeps publishing to itself";
  }

  LcmBus bus_;
  NodeContext ctx_;
  std::unique_ptr<Node> node_;
  std::vector<std::unique_ptr<SinkBase>> sinks_;
};

// The seqs of collected messages, in the order they were published.
template <typename Msg>
std::vector<int64_t> Seqs(const std::deque<Msg>& messages) {
  std::vector<int64_t> seqs;
  for (const Msg& m : messages) seqs.push_back(m.seq);
  return seqs;
}

}  // namespace dmpl::testing
