// dmpl_hand_geometry --config FILE: the hand model of a config (its `hand` section, the URDF the
// simulator and the kinematics read) as JSON on stdout: links with their shapes, joints with
// their origins, axes and (revolute, finite) limits. The viewer draws from it and grasp-room
// places fingers with it, so the picture, the analysis and the physics share one parser. Exit 2
// with one message on a bad config or URDF.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "components/hand/hand_model.h"
#include "components/logging/json_text.h"
#include "components/runtime/command_line.h"
#include "components/runtime/config.h"

namespace {

void PrintPose(const Eigen::Isometry3d& pose) {
  // Row-major 4x4.
  std::printf("[");
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::printf("%s%.17g", r + c == 0 ? "" : ", ", pose.matrix()(r, c));
    }
  }
  std::printf("]");
}

void Print(const dmpl::HandModel& hand) {
  using dmpl::CollisionShape;
  std::printf("{\"links\": [");
  for (size_t i = 0; i < hand.links().size(); ++i) {
    const auto& link = hand.links()[i];
    std::printf("%s\n  {\"name\": %s, \"shapes\": [", i ? "," : "", dmpl::JsonString(link.name).c_str());
    for (size_t k = 0; k < link.collisions.size(); ++k) {
      const CollisionShape& s = link.collisions[k];
      const char* kind = s.kind == CollisionShape::Kind::kBox      ? "box"
                         : s.kind == CollisionShape::Kind::kSphere ? "sphere"
                                                                   : "cylinder";
      std::printf("%s{\"kind\": \"%s\", \"size\": ", k ? ", " : "", kind);
      if (s.kind == CollisionShape::Kind::kBox) {
        std::printf("[%.17g, %.17g, %.17g]", s.box_size.x(), s.box_size.y(), s.box_size.z());
      } else if (s.kind == CollisionShape::Kind::kSphere) {
        std::printf("[%.17g]", s.radius);
      } else {
        std::printf("[%.17g, %.17g]", s.radius, s.length);
      }
      std::printf(", \"origin\": ");
      PrintPose(s.origin);
      std::printf("}");
    }
    std::printf("]}");
  }
  std::printf("],\n\"joints\": [");
  for (size_t j = 0; j < hand.joints().size(); ++j) {
    const auto& joint = hand.joints()[j];
    std::printf("%s\n  {\"name\": %s, \"type\": \"%s\", \"parent\": %s, \"child\": %s, ", j ? "," : "",
                dmpl::JsonString(joint.name).c_str(),
                joint.type == dmpl::JointInfo::Type::kRevolute ? "revolute" : "fixed",
                dmpl::JsonString(hand.links()[joint.parent_link].name).c_str(),
                dmpl::JsonString(hand.links()[joint.child_link].name).c_str());
    std::printf("\"axis\": [%.17g, %.17g, %.17g], ", joint.axis.x(), joint.axis.y(),
                joint.axis.z());
    if (joint.type == dmpl::JointInfo::Type::kRevolute && std::isfinite(joint.lower) &&
        std::isfinite(joint.upper)) {
      std::printf("\"lower\": %.17g, \"upper\": %.17g, ", joint.lower, joint.upper);
    }
    std::printf("\"origin\": ");
    PrintPose(joint.origin);
    std::printf("}");
  }
  std::printf("]}\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dmpl_hand_geometry: the hand model of a config (links, shapes, joints) as JSON",
               "dmpl_hand_geometry"};
  std::string config_path;
  app.add_option("--config", config_path, "the config whose hand section is read (default: the "
                                          "default hand)")
      ->type_name("FILE");
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  try {
    const dmpl::Config config = dmpl::Config::Resolve(config_path, {}, {});
    dmpl::HandParams params;
    config.Load("hand", &params);
    Print(dmpl::HandModel::Load(params));
  } catch (const std::exception& e) {
    std::cerr << "dmpl_hand_geometry: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
