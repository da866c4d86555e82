#pragma once
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

  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit(DMPL_NVP(urdf));
    a->Visit(DMPL_NVP(fingers));
    a->Visit(DMPL_NVP(tip_radius));
  }
};

// Resolves a project-relative path: absolute stays, relative is taken from $DMPL_ROOT when set,
// else from the working directory.
std::string ResolveProjectPath(const std::string& path);

}  // namespace dmpl
