#pragma once
// For tests: the paper's sphere held by four fingertips. The initial joint angles put the tip
// centres 4 mm inside the sphere's surface + tip radius, so each servo presses by its stiffness;
// SqueezeTargets() then squeezes the held object a little more.
#include <vector>

#include "sim_process/sim/sim_params.h"

namespace dmpl::testing {

inline SimParams StaticGraspSim() {
  SimParams sim;
  sim.initial_joints = {{"T", {1.0805, 0.6818, 0.7742, 0.8128}},
                        {"F", {-0.2086, 0.6651, 0.8474, 0.7633}},
                        {"M", {0.0, 0.5752, 0.7849, 0.7381}},
                        {"R", {0.2086, 0.6651, 0.8474, 0.7633}}};
  return sim;
}

inline std::vector<double> SqueezeTargets() {
  return {1.1372, 0.6229, 0.7914, 0.7343, -0.2385, 0.692, 0.8536, 0.7619,
          0.0,    0.5904, 0.8202, 0.7605, 0.2385,  0.692, 0.8536, 0.7619};
}

}  // namespace dmpl::testing
