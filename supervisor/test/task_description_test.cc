#include <gtest/gtest.h>

#include "supervisor/task_description.h"

namespace dmpl {
namespace {

const std::vector<std::string> kFingers = {"T", "F", "M", "R"};

TEST(TaskDescriptionTest, TheShippedTaskFilesLoad) {
  for (const char* name : {"fig8_rotate", "fig9_explore", "fig10_gait"}) {
    const TaskFile t =
        LoadTaskFile(std::string(DMPL_SOURCE_DIR) + "/configs/tasks/" + name + ".yaml", kFingers);
    EXPECT_EQ(t.name, name);
    EXPECT_EQ(t.grasp.approach.size(), 4u);
    EXPECT_FALSE(t.tasks.empty());
  }
  const TaskFile fig9 =
      LoadTaskFile(std::string(DMPL_SOURCE_DIR) + "/configs/tasks/fig9_explore.yaml", kFingers);
  const auto& ring = fig9.tasks[0].fingers.at("R");
  ASSERT_EQ(ring.size(), 3u);
  EXPECT_EQ(ring[0].primitive, Primitive::kHybrid);
  EXPECT_EQ(ring[0].role, Role::kExplore);
  EXPECT_EQ(ring[0].until, Condition::kDuration);
  EXPECT_TRUE(ring[0].has_target);
  const TaskFile fig8 =
      LoadTaskFile(std::string(DMPL_SOURCE_DIR) + "/configs/tasks/fig8_rotate.yaml", kFingers);
  ASSERT_TRUE(fig8.tasks[0].motion);
  EXPECT_EQ(fig8.tasks[0].fingers.at("all")[0].entry.contact, ContactState::kTouching);
  EXPECT_EQ(fig8.tasks[1].motion->reference, ObjectMotion::Reference::kStart);
}

std::string Error(const std::string& yaml) {
  try {
    ParseTaskFile(YAML::Load(yaml), "bad.yaml", kFingers);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(TaskDescriptionTest, BadTaskFilesGiveClearErrors) {
  const std::string one = "tasks: [{name: t, fingers: {all: [{primitive: composite}]}, ";
  EXPECT_NE(Error("name: x\n").find("at least one task"), std::string::npos);
  EXPECT_NE(Error(one + "done_when: duration, duration_s: 1, colour: red}]").find("unknown key 'tasks[0].colour'"),
            std::string::npos);
  EXPECT_NE(Error(one + "done_when: soon}]").find("'soon' is not one of"), std::string::npos);
  EXPECT_NE(Error("tasks: [{fingers: {X: [{primitive: hold}]}, done_when: duration, duration_s: 1}]")
                .find("no finger 'X'"),
            std::string::npos);
  EXPECT_NE(Error("tasks: [{fingers: {T: [{primitive: grab}]}, done_when: duration, duration_s: 1}]")
                .find("tasks[0].fingers.T[0].primitive"),
            std::string::npos);
  EXPECT_NE(Error("tasks: [{fingers: {T: [{primitive: position}]}, done_when: duration, duration_s: 1}]")
                .find("needs a target point"),
            std::string::npos);
  EXPECT_NE(Error(one + "done_when: motion_done}]").find("motion_done needs an object_motion"),
            std::string::npos);
  EXPECT_NE(Error(one + "done_when: duration}]").find("duration_s > 0"), std::string::npos);
  EXPECT_NE(Error("gait: {order: [R, M]}\n" + one + "done_when: duration, duration_s: 1}]")
                .find("gait.order"),
            std::string::npos);
  EXPECT_NE(Error("grasp: {approach: {T: [0, 0, 0]}}\n" + one + "done_when: duration, duration_s: 1}]")
                .find("every finger"),
            std::string::npos);
  EXPECT_NE(Error(one + "done_when: duration, duration_s: 1, object_motion: {axis: w}}]")
                .find("object_motion.axis"),
            std::string::npos);
  EXPECT_NE(Error("tasks: 3").find("bad.yaml"), std::string::npos);
  // The bounds declared beside the grasp's and the gait's fields, naming the file and the key.
  const std::string tilted = Error("gait: {overlap_max_tilt_rad: 2}\n" + one +
                                   "done_when: duration, duration_s: 1}]");
  EXPECT_NE(tilted.find("bad.yaml"), std::string::npos) << tilted;
  EXPECT_NE(tilted.find("gait.overlap_max_tilt_rad"), std::string::npos) << tilted;
  EXPECT_NE(Error("grasp: {timeout_s: 0}\n" + one + "done_when: duration, duration_s: 1}]")
                .find("grasp.timeout_s"),
            std::string::npos);
}

}  // namespace
}  // namespace dmpl
