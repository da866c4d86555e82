// The supervisor node's protocol over memq://: each controller report answered once with the
// task for the ticks after it; reports the controller cannot have sent are refused.
#include <gtest/gtest.h>

#include <limits>

#include "components/runtime/channels.h"
#include "components/runtime/testing/node_harness.h"
#include "dmpl/controller_status_t.hpp"
#include "dmpl/task_cmd_t.hpp"
#include "supervisor/supervisor_node.h"
#include "supervisor/supervisor_translation.h"

namespace dmpl {
namespace {

using testing::NodeHarness;

class SupervisorNodeTest : public ::testing::Test {
 protected:
  SupervisorNodeTest()
      : harness_(kSupervisorNode,
                 {"run.lockstep=true", "task.file=configs/tasks/fig8_rotate.yaml"}),
        tasks_(harness_.Collect<task_cmd_t>(channels::kTask)) {}

  // The controller's report of tick `seq`: the object 8 cm off the palm, nothing touching.
  static controller_status_t Report(int64_t seq) {
    controller_status_t m{};
    m.seq = seq;
    m.utime = seq * 1000;
    m.object_position[0] = 0.08;
    m.object_orientation[0] = 1.0;
    for (const char* name : {"T", "F", "M", "R"}) {
      finger_status_t f{};
      f.finger = name;
      f.tip_position[0] = 0.05;
      m.fingers.push_back(f);
    }
    m.num_fingers = 4;
    return m;
  }

  std::vector<int64_t> TaskSeqs() const { return testing::Seqs(tasks_); }

  NodeHarness harness_;
  std::deque<task_cmd_t>& tasks_;
};

TEST_F(SupervisorNodeTest, EachReportIsAnsweredOnceWithATaskForEveryFinger) {
  harness_.Publish(channels::kControllerReport, Report(0));
  harness_.Publish(channels::kControllerReport, Report(0));  // sent again after a loss
  harness_.Publish(channels::kControllerReport, Report(10));
  ASSERT_EQ(TaskSeqs(), (std::vector<int64_t>{0, 10}));
  const task_cmd_t& t = tasks_.front();
  EXPECT_EQ(t.name, "approach");  // the grasp chart starts at the first report
  ASSERT_EQ(t.num_fingers, 4);
  for (const finger_primitive_t& f : t.fingers) EXPECT_TRUE(f.has_target) << f.finger;
}

TEST_F(SupervisorNodeTest, ReportsTheControllerCannotHaveSentAreRefused) {
  harness_.Publish(channels::kControllerReport, Report(0));
  controller_status_t nan = Report(10);
  nan.object_orientation[2] = std::numeric_limits<double>::quiet_NaN();
  harness_.Publish(channels::kControllerReport, nan);
  controller_status_t crushing = Report(10);
  crushing.fingers[1].force_n = 1e9;
  harness_.Publish(channels::kControllerReport, crushing);
  harness_.Publish(channels::kControllerReport, Report(100000000));  // forged, far ahead
  harness_.PublishBytes(channels::kControllerReport, "garbage");
  EXPECT_EQ(TaskSeqs(), (std::vector<int64_t>{0}));
  EXPECT_EQ(harness_.node().undecodable(), 1);
  harness_.Publish(channels::kControllerReport, Report(10));  // the real one is still answered
  EXPECT_EQ(TaskSeqs(), (std::vector<int64_t>{0, 10}));
}

// The controller's gravity reaches the supervisor as a unit direction, or not at all: a report
// from outside may carry zeros, NaN or an acceleration instead.
TEST(SupervisorTranslationTest, GravityIsADirectionOrNothing) {
  const std::vector<std::string> fingers = {"T", "F", "M", "R"};
  auto view_of = [&](double x, double y, double z) {
    controller_status_t m{};
    m.object_orientation[0] = 1.0;
    m.gravity[0] = x, m.gravity[1] = y, m.gravity[2] = z;
    return ToControllerView(m, fingers).gravity;
  };
  EXPECT_TRUE(view_of(0, 0, -1).isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_TRUE(view_of(0, 0, 0).isZero());
  EXPECT_TRUE(view_of(0, 0, -9.81).isZero());
  EXPECT_TRUE(view_of(std::numeric_limits<double>::quiet_NaN(), 0, -1).isZero());
}

// What the controller has observed of the object is a positive number, or nothing yet.
TEST(SupervisorTranslationTest, ObservedFrictionAndWeightArePositiveOrNothing) {
  const std::vector<std::string> fingers = {"T", "F", "M", "R"};
  auto view_of = [&](double friction, double weight) {
    controller_status_t m{};
    m.object_orientation[0] = 1.0;
    m.observed_friction = friction;
    m.observed_weight_n = weight;
    return ToControllerView(m, fingers);
  };
  EXPECT_DOUBLE_EQ(view_of(0.8, 0.49).observed_friction, 0.8);
  EXPECT_DOUBLE_EQ(view_of(0.8, 0.49).observed_weight_n, 0.49);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double bad : {0.0, -1.0, nan, std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(view_of(bad, bad).observed_friction, 0.0) << bad;
    EXPECT_EQ(view_of(bad, bad).observed_weight_n, 0.0) << bad;
  }
}

}  // namespace
}  // namespace dmpl
