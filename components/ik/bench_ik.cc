// dmpl_bench_ik: one four-finger IK solve (Google Benchmark), tracking targets that move like a
// manipulation does (a few mm per second), warm started as in the IK server.
// `dmpl_bench_ik --percentiles N` times N solves one by one and prints JSON with the median and
// p99 (what `tools/dmpl bench ik` reports); Google Benchmark's flags go to Google Benchmark.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "components/ik/hand_ik.h"
#include "components/runtime/command_line.h"

namespace {

// Tracks targets that rotate the tips about the sphere's x axis by up to 0.2 rad at 0.1 rad/s.
class Scenario {
 public:
  Scenario()
      : model_(Load()), kin_(model_), ik_(kin_, dmpl::IkParams{}), targets_(4) {
    for (int f = 0; f < 4; ++f) base_.push_back(kin_.TipPosition(f, kGrasp));
    ik_.Step(kGrasp, targets_);
  }
  const std::vector<double>& Solve() {
    const double angle = 0.2 * std::sin(1e-3 * 0.5 * static_cast<double>(tick_++));
    const Eigen::AngleAxisd rot(angle, Eigen::Vector3d::UnitX());
    const Eigen::Vector3d centre(0.09, 0.0, 0.02);
    for (int f = 0; f < 4; ++f) targets_[f] = centre + rot * (base_[f] - centre);
    return ik_.Step(kGrasp, targets_);
  }

 private:
  static dmpl::HandModel Load() {
    dmpl::HandParams hand;
    hand.urdf = std::string(DMPL_SOURCE_DIR) + "/configs/hand/dmpl_hand.urdf";
    return dmpl::HandModel::Load(hand);
  }
  // The grasp of the paper's sphere (configs/bench/sim_hold.yaml, contact joints).
  inline static const std::vector<double> kGrasp = {
      1.0805, 0.6818, 0.7742, 0.8128, -0.2086, 0.6651, 0.8474, 0.7633,
      0.0,    0.5752, 0.7849, 0.7381, 0.2086,  0.6651, 0.8474, 0.7633};
  dmpl::HandModel model_;
  dmpl::HandKinematics kin_;
  dmpl::HandIk ik_;
  std::vector<Eigen::Vector3d> base_;
  std::vector<std::optional<Eigen::Vector3d>> targets_;
  int64_t tick_ = 0;
};

void BM_FourFingerIk(benchmark::State& state) {
  Scenario scenario;
  for (auto _ : state) benchmark::DoNotOptimize(scenario.Solve());
}
BENCHMARK(BM_FourFingerIk)->Unit(benchmark::kMicrosecond);

int Percentiles(int n) {
  Scenario scenario;
  for (int i = 0; i < 1000; ++i) scenario.Solve();  // warm up
  std::vector<double> us(n);
  for (int i = 0; i < n; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(scenario.Solve());
    us[i] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  }
  std::sort(us.begin(), us.end());
  std::printf("{\"ik_solve_us_median\": %.3f, \"ik_solve_us_p99\": %.3f, \"solves\": %d}\n",
              us[n / 2], us[n * 99 / 100], n);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dmpl_bench_ik: one four-finger IK solve, timed (Google Benchmark)",
               "dmpl_bench_ik"};
  int solves = 0;
  app.add_option("--percentiles", solves,
                 "time N solves one by one and print their median and p99 as JSON")
      ->type_name("N")
      ->check(dmpl::IntegerAtLeast(1));
  app.allow_extras();
  app.footer("Google Benchmark's own flags (--benchmark_filter=REGEX, ...) are passed on to it.");
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  // What CLI11 did not take goes to Google Benchmark, which refuses what it does not know.
  std::string program = app.get_name();
  std::vector<std::string> extras = app.remaining();
  std::vector<char*> bench_argv = {program.data()};
  for (std::string& arg : extras) bench_argv.push_back(arg.data());
  int bench_argc = static_cast<int>(bench_argv.size());
  benchmark::Initialize(&bench_argc, bench_argv.data());
  if (benchmark::ReportUnrecognizedArguments(bench_argc, bench_argv.data())) return 2;
  if (solves > 0) return Percentiles(solves);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
