#pragma once
#include <array>
#include <string>
#include <vector>

#include "components/runtime/params.h"

namespace dmpl {

struct FingerParams {
  std::string name;
  std::string tip_link;  // the link whose origin is the fingertip sphere centre
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(name));
    a->Visit(DMPL_NVP(tip_link));
  }
};

// Section `hand`: which URDF, and which links are the fingertips. The simulator and the IK
// server read the same section, so they always agree on the hand.
struct HandParams {
  std::string urdf = "configs/hand/dmpl_hand.urdf";  // relative paths: from $DMPL_ROOT
  std::vector<FingerParams> fingers = {
      {"T", "T_tip"}, {"F", "F_tip"}, {"M", "M_tip"}, {"R", "R_tip"}};
  double tip_radius = 0.012;  // m; the controller offsets contact points by it
  // Link pairs that never collide with each other (parent/child pairs never do), like an SRDF's
  // disabled collisions. The thumb's base is mounted inside the palm's box: without this the palm
  // pins T_link1 and the thumb cannot turn its first joint below ~1.07 rad.
  std::vector<std::array<std::string, 2>> self_collision_exclude = {{"palm", "T_link1"}};

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(urdf));
    a->Visit(DMPL_NVP(fingers));
    a->Visit(DMPL_NVP(tip_radius));
    a->Visit(DMPL_NVP(self_collision_exclude));
  }
};

// Resolves a project-relative path: absolute stays, relative is taken from $DMPL_ROOT when set,
// else from the working directory.
std::string ResolveProjectPath(const std::string& path);

}  // namespace dmpl
