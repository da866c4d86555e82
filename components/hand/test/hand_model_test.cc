#include <gtest/gtest.h>

#include <fstream>

#include "components/hand/hand_model.h"

namespace dmpl {
namespace {

HandParams DefaultHand() {
  HandParams p;
  p.urdf = std::string(DMPL_SOURCE_DIR) + "/configs/hand/dmpl_hand.urdf";
  return p;
}

TEST(HandModelTest, LoadsTheHandWithFourFingersOfFourJoints) {
  const HandModel model = HandModel::Load(DefaultHand());
  ASSERT_EQ(model.fingers().size(), 4u);
  EXPECT_EQ(model.num_actuated(), 16);
  EXPECT_EQ(model.fingers()[0].name, "T");
  for (const auto& f : model.fingers()) EXPECT_EQ(f.joints.size(), 4u) << f.name;
  EXPECT_EQ(model.actuated_names()[4], "F_j0");
  EXPECT_EQ(model.links()[0].name, "palm");
  for (size_t l = 1; l < model.links().size(); ++l) {
    EXPECT_LT(model.links()[l].parent_link, static_cast<int>(l)) << "parents before children";
    EXPECT_GT(model.links()[l].mass, 0.0);
  }
}

std::string WriteUrdf(const std::string& body) {
  const std::string path = ::testing::TempDir() + "/dmpl_bad.urdf";
  std::ofstream(path) << "<?xml version=\"1.0\"?><robot name=\"r\">" << body << "</robot>";
  return path;
}

std::string LoadError(const std::string& body, std::vector<FingerParams> fingers = {{"A", "tip"}}) {
  HandParams p;
  p.urdf = WriteUrdf(body);
  p.fingers = fingers;
  p.self_collision_exclude.clear();  // the default names links of dmpl_hand.urdf
  try {
    HandModel::Load(p);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

const char* kInertial =
    "<inertial><mass value=\"0.1\"/><inertia ixx=\"1e-5\" iyy=\"1e-5\" izz=\"1e-5\" ixy=\"0\" "
    "ixz=\"0\" iyz=\"0\"/></inertial>";

std::string Link(const std::string& name, const std::string& inertial = kInertial) {
  return "<link name=\"" + name + "\">" + inertial + "</link>";
}

TEST(HandModelTest, BadUrdfsGiveClearErrors) {
  EXPECT_NE(LoadError("").find("could not parse"), std::string::npos);
  // urdfdom's own reason is in the error, not only on stderr.
  const std::string dangling =
      Link("base") + "<joint name=\"j\" type=\"fixed\"><parent link=\"base\"/>"
                     "<child link=\"nope\"/></joint>";
  EXPECT_NE(LoadError(dangling).find("child link [nope] of joint [j] not found"),
            std::string::npos)
      << LoadError(dangling);
  HandParams missing;
  missing.urdf = "/nonexistent/hand.urdf";
  EXPECT_THROW(HandModel::Load(missing), ConfigError);
  const std::string floating =
      Link("base") + Link("tip") +
      "<joint name=\"j\" type=\"floating\"><parent link=\"base\"/><child link=\"tip\"/></joint>";
  EXPECT_NE(LoadError(floating).find("joint 'j' is floating"), std::string::npos);
  const std::string planar =
      Link("base") + Link("tip") +
      "<joint name=\"p\" type=\"planar\"><parent link=\"base\"/><child link=\"tip\"/>"
      "<axis xyz=\"0 0 1\"/></joint>";
  EXPECT_NE(LoadError(planar).find("planar"), std::string::npos);
  const std::string massless =
      Link("base") + Link("tip", "<inertial><mass value=\"0\"/><inertia ixx=\"1\" iyy=\"1\" "
                                 "izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>") +
      "<joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"tip\"/>"
      "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>";
  EXPECT_NE(LoadError(massless).find("non-positive mass"), std::string::npos);
  const std::string ok =
      Link("base") + Link("tip") +
      "<joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"tip\"/>"
      "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>";
  EXPECT_EQ(LoadError(ok), "");
  EXPECT_NE(LoadError(ok, {{"A", "nope"}}).find("tip link 'nope' is not in the URDF"),
            std::string::npos);
  EXPECT_NE(LoadError(ok, {}).find("hand.fingers is empty"), std::string::npos);
}

TEST(HandModelTest, CollisionExclusionsNameLinksOfTheUrdf) {
  const HandModel model = HandModel::Load(DefaultHand());
  const int palm = model.FindLink("palm"), t1 = model.FindLink("T_link1");
  EXPECT_TRUE(model.CollisionExcluded(t1, palm));
  EXPECT_TRUE(model.CollisionExcluded(palm, t1));
  EXPECT_FALSE(model.CollisionExcluded(palm, model.FindLink("F_link1")));
  HandParams bad = DefaultHand();
  bad.self_collision_exclude = {{"palm", "T_link1"}, {"palm", "thumb_typo"}};
  try {
    HandModel::Load(bad);
    FAIL() << "an unknown link was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("hand.self_collision_exclude[1]"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("thumb_typo"), std::string::npos);
  }
  bad.self_collision_exclude = {{"palm", "palm"}};
  EXPECT_THROW(HandModel::Load(bad), ConfigError);
}

}  // namespace
}  // namespace dmpl
