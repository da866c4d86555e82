// The IK node's protocol over memq://: each tick's targets answered once and in order, a lost
// tick waited for, bad and forged input refused without silencing the node.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "components/hand/hand_model.h"
#include "components/ik/ik_node.h"
#include "components/runtime/channels.h"
#include "components/runtime/testing/node_harness.h"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/joint_cmd_t.hpp"

namespace dmpl {
namespace {

using testing::NodeHarness;

class IkNodeTest : public ::testing::Test {
 protected:
  IkNodeTest() : harness_(kIkNode, {"run.lockstep=true"}), commands_(Commands()) {
    HandParams p;
    p.urdf = std::string(DMPL_SOURCE_DIR) + "/configs/hand/dmpl_hand.urdf";
    model_ = HandModel::Load(p);
  }

  std::deque<joint_cmd_t>& Commands() { return harness_.Collect<joint_cmd_t>(channels::kJointCmd); }

  // The targets of tick `seq`: every joint mid-range, every finger holding.
  finger_targets_t Targets(int64_t seq) const {
    finger_targets_t t{};
    t.seq = seq;
    t.num_joints = static_cast<int16_t>(model_.num_actuated());
    for (int i = 0; i < model_.num_actuated(); ++i) {
      const JointInfo& j = model_.actuated_joint(i);
      t.joint_position.push_back(0.5 * (j.lower + j.upper));
    }
    for (const FingerInfo& f : model_.fingers()) {
      finger_target_t ft{};
      ft.finger = f.name;
      ft.mode = finger_target_t::HOLD;
      t.fingers.push_back(ft);
    }
    t.num_fingers = static_cast<int8_t>(t.fingers.size());
    return t;
  }

  std::vector<int64_t> Seqs() const { return testing::Seqs(commands_); }

  NodeHarness harness_;
  std::deque<joint_cmd_t>& commands_;
  HandModel model_;
};

TEST_F(IkNodeTest, AnswersEachTickOnceWithACommandForEveryJoint) {
  harness_.Publish(channels::kFingerTargets, Targets(0));
  harness_.Publish(channels::kFingerTargets, Targets(1));
  harness_.Publish(channels::kFingerTargets, Targets(1));  // sent again after a loss
  ASSERT_EQ(Seqs(), (std::vector<int64_t>{0, 1}));
  const joint_cmd_t& c = commands_.back();
  EXPECT_EQ(c.num_joints, model_.num_actuated());
  EXPECT_EQ(c.name, model_.actuated_names());
  // Every finger holds: the command is the joints it was planned from.
  for (int i = 0; i < model_.num_actuated(); ++i) {
    EXPECT_NEAR(c.position[i], Targets(1).joint_position[i], 1e-12) << c.name[i];
  }
}

TEST_F(IkNodeTest, ALostTickIsWaitedForAndTheTicksAfterItFollowInOrder) {
  harness_.Publish(channels::kFingerTargets, Targets(0));
  harness_.Publish(channels::kFingerTargets, Targets(2));
  harness_.Publish(channels::kFingerTargets, Targets(3));
  EXPECT_EQ(Seqs(), (std::vector<int64_t>{0}));  // 1 is missing: nothing after it is computed
  harness_.Publish(channels::kFingerTargets, Targets(1));
  EXPECT_EQ(Seqs(), (std::vector<int64_t>{0, 1, 2, 3}));
}

TEST_F(IkNodeTest, BadInputIsRefusedAndTheNextTickStillAnswered) {
  harness_.Publish(channels::kFingerTargets, Targets(0));
  finger_targets_t nan = Targets(1);
  nan.joint_position[3] = std::numeric_limits<double>::quiet_NaN();
  harness_.Publish(channels::kFingerTargets, nan);
  finger_targets_t beyond = Targets(1);
  beyond.joint_position[0] = 1e300;
  harness_.Publish(channels::kFingerTargets, beyond);
  finger_targets_t far = Targets(1);
  far.fingers[0].mode = finger_target_t::POSITION;
  far.fingers[0].position[0] = 2.0;  // 2 m from the palm
  harness_.Publish(channels::kFingerTargets, far);
  harness_.PublishBytes(channels::kFingerTargets, "not a message");
  EXPECT_EQ(Seqs(), (std::vector<int64_t>{0}));
  EXPECT_EQ(harness_.node().undecodable(), 1);
  harness_.Publish(channels::kFingerTargets, Targets(1));
  EXPECT_EQ(Seqs(), (std::vector<int64_t>{0, 1}));
  for (double q : commands_.back().position) EXPECT_TRUE(std::isfinite(q));
}

TEST_F(IkNodeTest, AForgedSeqFarAheadDoesNotSilenceTheNode) {
  harness_.Publish(channels::kFingerTargets, Targets(0));
  harness_.Publish(channels::kFingerTargets, Targets(1000000));
  harness_.Publish(channels::kFingerTargets, Targets(1));
  harness_.Publish(channels::kFingerTargets, Targets(2));
  EXPECT_EQ(Seqs(), (std::vector<int64_t>{0, 1, 2}));
}

// In a run with an identity (run.run_id), a loop message without it (sent by hand, or forged) or
// with another run's is not taken; a node started by hand (the fixture's) takes every message.
TEST_F(IkNodeTest, InARunWithAnIdentityOnlyTheRunsOwnTicksAreTaken) {
  NodeHarness run(kIkNode, {"run.lockstep=true", "run.run_id=7"});
  std::deque<joint_cmd_t>& commands = run.Collect<joint_cmd_t>(channels::kJointCmd);
  finger_targets_t targets = Targets(0);
  run.Publish(channels::kFingerTargets, targets);  // run_id 0
  targets.run_id = 5;
  run.Publish(channels::kFingerTargets, targets);
  EXPECT_TRUE(commands.empty());
  targets.run_id = 7;
  run.Publish(channels::kFingerTargets, targets);
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands.back().seq, 0);
  EXPECT_EQ(commands.back().run_id, 7);
}

}  // namespace
}  // namespace dmpl
