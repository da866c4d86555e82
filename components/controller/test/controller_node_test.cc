// The controller node's protocol over memq://: a tick runs once its sensed data and the task
// answering the last report are in; bad and forged input is refused without silencing it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "components/controller/controller_node.h"
#include "components/controller/controller_types.h"
#include "components/hand/hand_model.h"
#include "components/runtime/channels.h"
#include "components/runtime/testing/node_harness.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/finger_targets_t.hpp"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/task_cmd_t.hpp"

namespace dmpl {
namespace {

using testing::NodeHarness;

class ControllerNodeTest : public ::testing::Test {
 protected:
  ControllerNodeTest()
      : harness_(kControllerNode, {"run.lockstep=true", "controller.node.report_period_ticks=10"}),
        targets_(harness_.Collect<finger_targets_t>(channels::kFingerTargets)),
        reports_(harness_.Collect<controller_status_t>(channels::kControllerReport)),
        statuses_(harness_.Collect<controller_status_t>(channels::kControllerStatus)) {
    HandParams p;
    p.urdf = std::string(DMPL_SOURCE_DIR) + "/configs/hand/dmpl_hand.urdf";
    model_ = HandModel::Load(p);
  }

  // What a hand senses at tick `seq`: joints mid-range, an object 8 cm off the palm, no contact.
  hand_sensors_t Sensors(int64_t seq) const {
    hand_sensors_t m{};
    m.seq = seq;
    m.utime = seq * 1000;
    joint_state_t& j = m.joints;
    j.seq = seq;
    j.num_joints = static_cast<int16_t>(model_.num_actuated());
    j.name = model_.actuated_names();
    for (int i = 0; i < model_.num_actuated(); ++i) {
      const JointInfo& info = model_.actuated_joint(i);
      j.position.push_back(0.5 * (info.lower + info.upper));
    }
    j.velocity.assign(j.num_joints, 0.0);
    j.effort.assign(j.num_joints, 0.0);
    m.object.seq = seq;
    m.object.valid = true;
    m.object.position[0] = 0.08;
    m.object.orientation[0] = 1.0;
    for (const FingerInfo& f : model_.fingers()) {
      fingertip_contact_t c{};
      c.finger = f.name;
      m.tactile.fingers.push_back(c);
    }
    m.tactile.num_fingers = static_cast<int8_t>(m.tactile.fingers.size());
    m.gravity[0] = -9.81;  // palm up
    return m;
  }

  // The supervisor's answer to the report of tick `seq`: every finger holds.
  static task_cmd_t Task(int64_t seq) {
    task_cmd_t t{};
    t.seq = seq;
    t.task_id = 1;
    t.name = "hold";
    t.object_orientation[0] = 1.0;
    return t;
  }

  std::vector<int64_t> TargetSeqs() const { return testing::Seqs(targets_); }

  NodeHarness harness_;
  std::deque<finger_targets_t>& targets_;
  std::deque<controller_status_t>& reports_;
  std::deque<controller_status_t>& statuses_;
  HandModel model_;
};

TEST_F(ControllerNodeTest, ATickWaitsForTheAnswerToTheLastReport) {
  harness_.Publish(channels::kSensors, Sensors(0));
  EXPECT_EQ(TargetSeqs(), (std::vector<int64_t>{0}));  // tick 0 waits for no task
  ASSERT_EQ(reports_.size(), 1u);                      // tick 0 is a report tick
  EXPECT_EQ(reports_.back().seq, 0);
  harness_.Publish(channels::kSensors, Sensors(1));
  harness_.Publish(channels::kSensors, Sensors(2));
  EXPECT_EQ(TargetSeqs(), (std::vector<int64_t>{0}));  // the answer to report 0 is missing
  harness_.Publish(channels::kTask, Task(0));
  EXPECT_EQ(TargetSeqs(), (std::vector<int64_t>{0, 1, 2}));
  // It serves ticks 1 to 10; tick 11 waits for the answer to report 10.
  for (int64_t k = 3; k <= 11; ++k) harness_.Publish(channels::kSensors, Sensors(k));
  EXPECT_EQ(targets_.back().seq, 10);
  EXPECT_EQ(reports_.back().seq, 10);
  harness_.Publish(channels::kTask, Task(10));
  EXPECT_EQ(targets_.back().seq, 11);
  // The targets carry the joints they were planned from, and a target for every finger.
  EXPECT_EQ(targets_.back().joint_position, Sensors(11).joints.position);
  EXPECT_EQ(targets_.back().num_fingers, static_cast<int>(model_.fingers().size()));
}

TEST_F(ControllerNodeTest, NaNInputIsRejectedTheLastTargetsHeldAndSaid) {
  harness_.Publish(channels::kSensors, Sensors(0));
  harness_.Publish(channels::kTask, Task(0));
  hand_sensors_t nan = Sensors(1);
  nan.object.position[1] = std::numeric_limits<double>::quiet_NaN();
  harness_.Publish(channels::kSensors, nan);
  ASSERT_EQ(TargetSeqs(), (std::vector<int64_t>{0, 1}));
  for (size_t f = 0; f < targets_[1].fingers.size(); ++f) {
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(targets_[1].fingers[f].position[i], targets_[0].fingers[f].position[i]);
    }
  }
  const controller_status_t& status = statuses_.back();
  EXPECT_EQ(status.seq, 1);
  ASSERT_EQ(status.num_events, 1);
  EXPECT_EQ(status.events[0].type, static_cast<int8_t>(EventType::kInputRejected));
  harness_.Publish(channels::kSensors, Sensors(2));  // and the next tick runs normally
  EXPECT_EQ(statuses_.back().num_events, 0);
}

TEST_F(ControllerNodeTest, ForgedAndUndecodableMessagesDoNotStopTheLoop) {
  harness_.Publish(channels::kSensors, Sensors(0));
  harness_.Publish(channels::kTask, Task(0));
  harness_.Publish(channels::kSensors, Sensors(5000000));  // forged, far ahead
  harness_.Publish(channels::kTask, Task(5000000));
  harness_.PublishBytes(channels::kSensors, std::string(7, '\xff'));
  harness_.Publish(channels::kSensors, Sensors(1));
  EXPECT_EQ(TargetSeqs(), (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(harness_.node().undecodable(), 1);
}

}  // namespace
}  // namespace dmpl
