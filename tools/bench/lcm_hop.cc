// dmpl_bench_lcm_hop: the raw one-way LCM latency between two processes on this machine, measured
// as half the round trip of a ping-pong of a message of a given size.
//   dmpl_bench_lcm_hop echo                       answers every ping (run it in another process)
//   dmpl_bench_lcm_hop ping [--bytes B] [--n N]   prints {"lcm_hop_us": ..., ...} as JSON
// Both use $LCM_DEFAULT_URL (or the LCM default).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

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
  if (argc < 2) {
    std::fprintf(stderr, "usage: dmpl_bench_lcm_hop echo | ping [--bytes B] [--n N]\n");
    return 2;
  }
  lcm::LCM lcm;
  if (!lcm.good()) return 3;
  const std::string mode = argv[1];
  if (mode == "echo") {
    Echo echo{&lcm};
    lcm.subscribe("DMPL_BENCH_PING", &Echo::On, &echo);
    while (lcm.handleTimeout(5000) > 0) {
    }
    return 0;  // 5 s without a ping: done
  }
  int bytes = 600, n = 5000;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--bytes") == 0) bytes = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--n") == 0) n = std::atoi(argv[i + 1]);
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
