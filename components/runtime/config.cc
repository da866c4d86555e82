#include "components/runtime/config.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace dmpl {

const std::vector<std::string>& KnownConfigSections() {
  static const std::vector<std::string> sections = {
      "run",   "hand",       "sim",        "object", "noise",     "ik",      "controller",
      "supervisor", "task",  "experiment", "processes", "joint_player", "metrics", "calibration"};
  return sections;
}

namespace {

// An experiment may build on another: `experiment: {base: other.yaml}` (relative to the file).
YAML::Node LoadWithBase(const std::string& file, int depth) {
  YAML::Node root = LoadYamlFile(file);
  const YAML::Node& const_root = root;
  if (!root.IsMap() || !const_root["experiment"] || !const_root["experiment"]["base"]) return root;
  if (depth > 8) throw ConfigError("config error in " + file + ": experiment.base nests too deep");
  const std::string base_name = const_root["experiment"]["base"].as<std::string>();
  const std::filesystem::path base_path =
      std::filesystem::path(file).parent_path() / std::filesystem::path(base_name);
  YAML::Node base = LoadWithBase(base_path.string(), depth + 1);
  root["experiment"].remove("base");
  MergeYaml(base, root);
  return base;
}

}  // namespace

Config Config::Resolve(const std::string& file, const std::vector<std::string>& params_files,
                       const std::vector<std::string>& set_overrides) {
  Config config;
  if (!file.empty()) {
    config.root_ = LoadWithBase(file, 0);
    config.source_ = file;
  }
  if (!config.root_.IsMap()) {
    throw ConfigError("config error in " + config.source_ + ": top level must be a map");
  }
  for (const auto& overlay_file : params_files) {
    const YAML::Node overlay = LoadYamlFile(overlay_file);
    if (!overlay.IsMap()) {
      throw ConfigError("config error in " + overlay_file + ": top level must be a map");
    }
    MergeYaml(config.root_, overlay);
    config.source_ += " + " + overlay_file;
  }
  for (const auto& assignment : set_overrides) ApplySetOverride(config.root_, assignment);
  if (!set_overrides.empty()) config.source_ += " + --set";

  const auto& known = KnownConfigSections();
  for (const auto& kv : config.root_) {
    const std::string key = kv.first.as<std::string>();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw ConfigError("config error in " + config.source_ + ": unknown section '" + key +
                        "'; known sections: " + list);
    }
  }
  return config;
}

std::string ResolveLcmUrl(const std::string& cli_url, const RunParams& run) {
  if (!cli_url.empty()) return cli_url;
  if (!run.lcm_url.empty()) return run.lcm_url;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env && *env) return env;
  return kDefaultLcmUrl;
}

Config Config::Without(const std::string& section) const {
  Config out;
  out.source_ = source_;
  out.root_ = YAML::Clone(root_);
  out.root_.remove(section);
  return out;
}

}  // namespace dmpl
