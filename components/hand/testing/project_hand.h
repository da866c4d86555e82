#pragma once
// For tests: the project's hand, as configs/hand/dmpl_hand.urdf describes it.
#include <string>

#include "components/hand/hand_model.h"

namespace dmpl::testing {

inline HandModel LoadHand() {
  HandParams p;
  p.urdf = std::string(DMPL_SOURCE_DIR) + "/configs/hand/dmpl_hand.urdf";
  return HandModel::Load(p);
}

}  // namespace dmpl::testing
