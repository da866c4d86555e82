#pragma once
// task.turn: who turns the object in a gait, parsed once from the config.
//   three:      the paper's A2..A11: the explorer reaches its point, then three turn
//   four:       the explorer moves while three hold still, grips again, then all four turn (A1)
//   continuous: three turn while the explorer slides
//   auto:       continuous when three can turn the object about the step's axis, else four
#include <stdexcept>
#include <string>

#include <yaml-cpp/yaml.h>

namespace dmpl {

enum class TurnMode { kThreeFingers, kFourFingers, kContinuous, kAuto };

inline const char* ToString(TurnMode m) {
  switch (m) {
    case TurnMode::kThreeFingers: return "three";
    case TurnMode::kFourFingers: return "four";
    case TurnMode::kContinuous: return "continuous";
    case TurnMode::kAuto: return "auto";
  }
  return "?";
}

// A config value holding a TurnMode (its YAML is the mode's name).
struct TurnParam {
  TurnMode mode = TurnMode::kThreeFingers;

  static TurnParam FromYaml(const YAML::Node& node) {
    const std::string text = node.IsScalar() ? node.Scalar() : "";
    for (TurnMode m : {TurnMode::kAuto, TurnMode::kContinuous, TurnMode::kFourFingers,
                       TurnMode::kThreeFingers}) {
      if (text == ToString(m)) return {m};
    }
    throw std::invalid_argument("must be 'auto', 'continuous', 'four' or 'three' (the paper's)");
  }
  YAML::Node ToYaml() const { return YAML::Node(ToString(mode)); }
};

}  // namespace dmpl
