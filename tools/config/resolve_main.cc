// dmpl_config: the resolved configuration of an experiment, as every node resolves it (its
// `experiment.base` chain, --params overlays, --set overrides, the known sections), printed as
// YAML. The Python tools read configs through it, so the rules are written once, in C++.
//
// usage: dmpl_config --config FILE [--params FILE]... [--set key=value]...
// Exit 0 with the YAML on stdout, or 2 with one line on stderr naming the file and the key.
#include <iostream>

#include "components/runtime/command_line.h"
#include "components/runtime/config.h"
#include "components/runtime/node.h"

int main(int argc, char** argv) {
  CLI::App app{"dmpl_config: the resolved configuration of an experiment, as YAML",
               "dmpl_config"};
  dmpl::NodeCommandLine cl;
  dmpl::AddConfigFlags(app, &cl);
  app.get_option("--config")->required();
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  try {
    const dmpl::Config config =
        dmpl::Config::Resolve(cl.config_file, cl.params_files, cl.set_overrides);
    std::cout << YAML::Dump(config.root()) << "\n";
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
  return 0;
}
