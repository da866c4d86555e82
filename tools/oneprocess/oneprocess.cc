// dmpl_oneprocess: every node of an experiment in one process, on one memq:// bus, in lockstep.
// Same configuration, same messages, same results as the multi-process run for the same seed;
// no sockets, no scheduler between the nodes. The fast path for Monte-Carlo runs, and the
// baseline that the multi-process overhead is measured against.
//
// usage: dmpl_oneprocess --config EXPERIMENT.yaml [--set key=value]... [--params FILE]...
//                        [--record FILE] [--record-policy full|analysis|none] [--columns DIR]
//                        [--columns-fields REGEX]
// The experiment's `processes` say which nodes run (by their executables' names).
#include <csignal>
#include <iostream>
#include <list>
#include <map>

#include "components/runtime/clock.h"
#include "components/runtime/command_line.h"
#include "components/runtime/log_recorder.h"
#include "components/controller/controller_node.h"
#include "components/ik/ik_node.h"
#include "sim_process/joint_player/joint_player_node.h"
#include "sim_process/noise/noise_node.h"
#include "sim_process/sim/sim_node.h"
#include "supervisor/supervisor_node.h"

namespace {

// Every kind of node, by the name of its executable: the experiment's `processes` name them.
const std::map<std::string, const dmpl::NodeInfo*>& Registry() {
  static const std::map<std::string, const dmpl::NodeInfo*> registry = [] {
    std::map<std::string, const dmpl::NodeInfo*> r;
    for (const dmpl::NodeInfo* n : {&dmpl::kSimNode, &dmpl::kNoiseNode, &dmpl::kJointPlayerNode,
                                    &dmpl::kIkNode, &dmpl::kControllerNode, &dmpl::kSupervisorNode}) {
      r[n->name] = n;
    }
    return r;
  }();
  return registry;
}

// A node's config flags (AddConfigFlags), and the recorder's.
struct OneProcessCommandLine {
  dmpl::NodeCommandLine node;
  dmpl::RecordOptions record;
  std::string policy;
};

void AddRecorderFlags(CLI::App& app, OneProcessCommandLine* cl) {
  app.add_option("--record", cl->record.log_path, "record the bus to this LCM log")
      ->type_name("FILE");
  app.add_option("--record-policy", cl->policy,
                 "what the log keeps: full, analysis or none (default: run.record)")
      ->type_name("POLICY");
  app.add_option("--columns", cl->record.columns_dir,
                 "extract the metrics' columns of every message online into DIR")
      ->type_name("DIR");
  app.add_option("--columns-fields", cl->record.columns_fields,
                 "the fields extracted with --columns, as CHANNEL/name (a regex)")
      ->type_name("REGEX");
}

// The experiment's `processes`, each built by its kind's factory with a context of its own in
// `contexts` (which must outlive the nodes: a node may keep a reference to its context).
std::vector<std::unique_ptr<dmpl::Node>> MakeNodes(const dmpl::NodeContext& ctx,
                                                   std::list<dmpl::NodeContext>* contexts) {
  const YAML::Node processes = ctx.config.root()["processes"];
  if (!processes || !processes.IsSequence()) {
    throw dmpl::ConfigError("config error in " + ctx.config.source() +
                            ": no 'processes' list to take the nodes from");
  }
  std::vector<std::unique_ptr<dmpl::Node>> nodes;
  for (const auto& p : processes) {
    const std::string exec = p["exec"].as<std::string>();
    const auto it = Registry().find(exec);
    if (it == Registry().end()) {
      throw dmpl::ConfigError("config error in " + ctx.config.source() + ": process '" + exec +
                              "' has no one-process node");
    }
    // Only the simulator is given the object; the hand's own software senses it. (Built, never
    // assigned: assigning a YAML::Node rebinds the node it shares with ctx.config.)
    contexts->push_back(dmpl::NodeContext{
        p["name"] ? p["name"].as<std::string>() : exec,
        exec == "dmpl_sim" ? ctx.config : ctx.config.Without("object"), ctx.run, ctx.bus});
    nodes.push_back(it->second->make(contexts->back()));
  }
  return nodes;
}

// Runs the nodes until the loop ends; the exit code of the run.
int Run(dmpl::LcmBus* bus, const dmpl::RunParams& run,
        const std::vector<std::unique_ptr<dmpl::Node>>& nodes, dmpl::LogRecorder* recorder,
        spdlog::logger* log) {
  dmpl::InstallStopSignalHandlers();
  dmpl::Executor executor(bus, run.heartbeat_period_s);
  for (auto& n : nodes) executor.Add(n.get());
  const double t0 = dmpl::MonotonicSeconds();
  const int code = executor.Spin();
  while (bus->in_process()->DeliverOne()) {  // deliver what is still queued
  }
  if (recorder) {
    try {
      recorder->Finish();
    } catch (const std::exception& e) {
      log->critical("{}", e.what());
      return 1;
    }
  }
  log->info("{} nodes ran for {:.3f} s of wall time{}", nodes.size(), dmpl::MonotonicSeconds() - t0,
            recorder ? ", " + std::to_string(recorder->written()) + " messages recorded" : "");
  if (recorder && recorder->failed() > 0) return 1;
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dmpl_oneprocess: every node of an experiment in one process, on memq://, in "
               "lockstep",
               "dmpl_oneprocess"};
  OneProcessCommandLine cl;
  dmpl::AddConfigFlags(app, &cl.node);
  AddRecorderFlags(app, &cl);
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  dmpl::NodeContext ctx;
  try {
    ctx.config =
        dmpl::Config::Resolve(cl.node.config_file, cl.node.params_files, cl.node.set_overrides);
    ctx.config.Load("run", &ctx.run);
    ctx.run.Validate(ctx.config.source());
    cl.record.policy = dmpl::ParseRecordPolicy(cl.policy.empty() ? ctx.run.record : cl.policy);
    if (cl.record.log_path.empty()) cl.record.policy = dmpl::RecordPolicy::kNone;
    cl.record.run_id = ctx.run.run_id;
  } catch (const std::exception& e) {
    std::cerr << "dmpl_oneprocess: " << e.what() << "\n";
    return 2;
  }
  auto log = dmpl::MakeLogger("dmpl_oneprocess");
  if (!ctx.run.lockstep) {
    log->critical("one-process mode runs in lockstep only (run.lockstep is false)");
    return 2;
  }
  dmpl::LcmBus bus("memq://", false);  // the in-process queue
  ctx.bus = &bus;
  std::list<dmpl::NodeContext> contexts;  // before the nodes: destroyed after them
  std::vector<std::unique_ptr<dmpl::Node>> nodes;
  std::unique_ptr<dmpl::LogRecorder> recorder;
  try {
    nodes = MakeNodes(ctx, &contexts);
    if (!cl.record.log_path.empty() || !cl.record.columns_dir.empty()) {
      recorder = std::make_unique<dmpl::LogRecorder>(&bus, cl.record);
    }
  } catch (const std::exception& e) {
    log->critical("{}", e.what());
    return 2;
  }
  return Run(&bus, ctx.run, nodes, recorder.get(), log.get());
}
