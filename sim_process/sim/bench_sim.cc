// dmpl_bench_sim: wall time of one simulation step of the hand holding an object.
// usage: dmpl_bench_sim --config configs/bench/sim_hold.yaml [--engine bullet|mujoco]
//                       [--warmup N] [--steps N]
// Prints one JSON object: median/p90 step time in microseconds and the state of the grasp.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "components/runtime/clock.h"
#include "components/runtime/command_line.h"
#include "components/runtime/config.h"
#include "sim_process/joint_player/joint_trajectory.h"
#include "sim_process/sim/hand_sim.h"

int main(int argc, char** argv) {
  CLI::App app{"dmpl_bench_sim: wall time of one simulation step of the hand holding an object",
               "dmpl_bench_sim"};
  std::string config_file;
  std::string engine;
  int warmup = 500, steps = 3000;
  app.add_option("--config", config_file, "the scene (e.g. configs/bench/sim_hold.yaml)")
      ->type_name("FILE");
  app.add_option("--engine", engine, "the physics engine, over the config's sim.engine")
      ->check(CLI::IsMember({"bullet", "mujoco"}));
  app.add_option("--warmup", warmup, "steps run before timing (default 500)")
      ->type_name("N")
      ->check(dmpl::IntegerAtLeast(0));
  app.add_option("--steps", steps, "steps timed (default 3000)")
      ->type_name("N")
      ->check(dmpl::IntegerAtLeast(1));
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  try {
    const dmpl::Config config = dmpl::Config::Resolve(config_file, {}, {});
    dmpl::HandParams hand_params;
    dmpl::SimParams sim_params;
    dmpl::ObjectParams object;
    dmpl::JointPlayerParams player;
    config.Load("hand", &hand_params);
    config.Load("sim", &sim_params);
    config.Load("object", &object);
    config.Load("joint_player", &player);
    if (!engine.empty()) sim_params.engine = engine;
    const dmpl::HandModel model = dmpl::HandModel::Load(hand_params);
    dmpl::HandSim sim(model, sim_params, object);
    const dmpl::JointTrajectory trajectory(model, player.waypoints, config.source());
    std::string why;
    if (!sim.SetJointTargets(trajectory.At(0.0), &why)) throw dmpl::ConfigError(why);
    if (object.held) sim.ReleaseObject();
    for (int i = 0; i < warmup; ++i) sim.Step();
    const Eigen::Vector3d start = sim.object().pose.translation();
    std::vector<double> us(steps);
    for (int i = 0; i < steps; ++i) {
      const double t0 = dmpl::MonotonicSeconds();
      sim.Step();
      us[i] = (dmpl::MonotonicSeconds() - t0) * 1e6;
    }
    std::sort(us.begin(), us.end());
    int contacts = 0;
    for (const auto& t : sim.tactile()) contacts += t.in_contact ? 1 : 0;
    // The MuJoCo settings in effect, for a reference engine to mirror.
    const dmpl::MujocoParams& mj = sim_params.mujoco;
    std::printf(
        "{\"engine\": \"%s\", \"step_us_median\": %.3f, \"step_us_p90\": %.3f, \"steps\": %d, "
        "\"tips_in_contact\": %d, \"object_moved_m\": %.6g, \"mujoco\": {\"cone\": \"%s\", "
        "\"impratio\": %.17g, \"solref\": [%.17g, %.17g], \"solimp\": [%.17g, %.17g, %.17g], "
        "\"joint_damping\": %.17g, \"iterations\": %d, \"noslip_iterations\": %d, "
        "\"torsional_friction\": %.17g, \"rolling_friction\": %.17g, \"condim\": %d, "
        "\"collision\": \"%s\"}}\n",
        sim_params.engine.c_str(), us[steps / 2], us[steps * 9 / 10], steps, contacts,
        (sim.object().pose.translation() - start).norm(), mj.cone.c_str(), mj.impratio,
        mj.solref[0], mj.solref[1], mj.solimp[0], mj.solimp[1], mj.solimp[2], mj.joint_damping,
        mj.iterations, mj.noslip_iterations, mj.torsional_friction, mj.rolling_friction,
        mj.contact_dimension(), mj.collision.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dmpl_bench_sim: %s\n", e.what());
    return 2;
  }
  return 0;
}
