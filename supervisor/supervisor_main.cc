// dmpl_supervisor: the regrasp supervisor, as its own process. --dot / --mermaid print its
// statecharts instead.
#include <iostream>
#include <utility>
#include <vector>

#include "components/hand/hand_params.h"
#include "components/runtime/command_line.h"
#include "supervisor/supervisor.h"
#include "supervisor/supervisor_node.h"
#include "supervisor/task_description.h"

namespace {

// The grasp chart, then the regrasp chart for each way of turning (task.turn): Graphviz or Mermaid.
void PrintCharts(bool dot) {
  std::vector<std::string> fingers;  // the default hand's
  for (const dmpl::FingerParams& f : dmpl::HandParams{}.fingers) fingers.push_back(f.name);
  using dmpl::TurnMode;
  // Last, auto with task.grip_while_turning (what the gait configs use).
  const std::vector<std::pair<TurnMode, bool>> charts = {
      {TurnMode::kThreeFingers, false}, {TurnMode::kFourFingers, false},
      {TurnMode::kContinuous, false},   {TurnMode::kAuto, false},
      {TurnMode::kAuto, true}};
  for (const auto& [turn, grip_while_turning] : charts) {
    dmpl::TaskParams task;
    task.file = dmpl::ResolveProjectPath("configs/tasks/fig10_gait.yaml");
    task.turn.mode = turn;
    task.grip_while_turning = grip_while_turning;
    dmpl::Supervisor s(fingers, dmpl::LoadTaskFile(task.file, fingers), task,
                       dmpl::SupervisorParams{});
    if (turn == TurnMode::kThreeFingers) {
      std::cout << (dot ? s.GraspChartDot() : s.GraspChartMermaid()) << "\n";
    }
    std::cout << (dot ? "// " : "%% ") << "task.turn: " << ToString(turn)
              << (grip_while_turning ? ", task.grip_while_turning: true" : "") << "\n"
              << (dot ? s.RegraspChartDot() : s.RegraspChartMermaid());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const dmpl::NodeInfo& info = dmpl::kSupervisorNode;
  CLI::App app{std::string(info.name) +
                   ": the regrasp supervisor, a node of the dmpl loop; it reads the config "
                   "sections " +
                   info.reads,
               info.name};
  dmpl::NodeCommandLine cl;
  dmpl::AddNodeFlags(app, &cl);
  bool dot = false, mermaid = false;
  app.add_flag("--dot", dot, "print the statecharts for Graphviz and exit");
  app.add_flag("--mermaid", mermaid, "print the statecharts for Mermaid and exit");
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  if (dot || mermaid) {
    PrintCharts(dot);
    return 0;
  }
  return dmpl::RunNode(cl, info);
}
