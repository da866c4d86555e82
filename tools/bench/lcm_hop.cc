// dmpl_bench_lcm_hop: the raw one-way LCM latency between two processes on this machine, measured
// as half the round trip of a ping-pong of a message of a given size.
//   dmpl_bench_lcm_hop echo                       answers every ping (run it in another process)
//   dmpl_bench_lcm_hop ping [--bytes B] [--n N]   prints {"lcm_hop_us": ..., ...} as JSON
// Both use $LCM_DEFAULT_URL (or the LCM default).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "components/runtime/command_line.h"

namespace {

double Now() {
  return std::chrono::duration<double, std::micro>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

struct Echo {
  lcm::LCM* lcm;
  void On(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    lcm->publish("DMPL_BENCH_PONG", rbuf->data, rbuf->data_size);
  }
};

struct Ping {
  bool got = false;
  void On(const lcm::ReceiveBuffer*, const std::string&) { got = true; }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dmpl_bench_lcm_hop: the one-way LCM latency between two processes, as half a "
               "ping-pong's round trip (on $LCM_DEFAULT_URL)",
               "dmpl_bench_lcm_hop"};
  app.require_subcommand(1);
  CLI::App* echo_mode = app.add_subcommand("echo", "answer every ping (in another process)");
  CLI::App* ping_mode = app.add_subcommand("ping", "ping and print the latency as JSON");
  int bytes = 600, n = 5000;
  ping_mode->add_option("--bytes", bytes, "the message's size (default 600)")
      ->type_name("B")
      ->check(dmpl::IntegerAtLeast(1));
  ping_mode->add_option("--n", n, "round trips timed (default 5000)")
      ->type_name("N")
      ->check(dmpl::IntegerAtLeast(1));
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
  lcm::LCM lcm;
  if (!lcm.good()) {
    std::fprintf(stderr, "dmpl_bench_lcm_hop: cannot open LCM (is there a multicast route?)\n");
    return 3;
  }
  if (echo_mode->parsed()) {
    Echo echo{&lcm};
    lcm.subscribe("DMPL_BENCH_PING", &Echo::On, &echo);
    while (lcm.handleTimeout(5000) > 0) {
    }
    return 0;  // 5 s without a ping: done
  }
  Ping ping;
  lcm.subscribe("DMPL_BENCH_PONG", &Ping::On, &ping);
  std::vector<char> payload(bytes, 'x');
  std::vector<double> rtt;
  for (int i = 0; i < n + 200; ++i) {
    ping.got = false;
    const double t0 = Now();
    lcm.publish("DMPL_BENCH_PING", payload.data(), bytes);
    while (!ping.got) {
      if (lcm.handleTimeout(1000) <= 0) {
        std::fprintf(stderr, "dmpl_bench_lcm_hop: no pong (is the echo running?)\n");
        return 1;
      }
    }
    if (i >= 200) rtt.push_back(Now() - t0);  // after a warm-up
  }
  std::sort(rtt.begin(), rtt.end());
  std::printf("{\"lcm_hop_us\": %.2f, \"lcm_round_trip_us_median\": %.2f, "
              "\"lcm_round_trip_us_p99\": %.2f, \"bytes\": %d, \"round_trips\": %d}\n",
              rtt[rtt.size() / 2] / 2, rtt[rtt.size() / 2], rtt[rtt.size() * 99 / 100], bytes, n);
  return 0;
}
