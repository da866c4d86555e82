// dmpl_record: records LCM traffic to an LCM log file (the format of lcm-logger and lcm.EventLog).
//
// Why not lcm-logger: a 1 kHz lockstep run puts ~20 000 messages a second on the bus, and
// lcm-logger's subscription queue (LCM's default of 30 messages) overflows whenever it is
// descheduled for a millisecond or two; it then drops messages silently. Here the queue is large,
// and the exit code says whether every write succeeded.
//
// usage: dmpl_record [--lcm-url URL] [--channels REGEX] [--single-bus] [--policy P]
//                    [--columns DIR [--fields REGEX]] [--run-id N] [FILE]
// --run-id N: messages of another run (a run_id neither N nor 0) are neither logged nor extracted.
// Every bus of the URL is recorded (channels.h), unless --single-bus. --policy (full, analysis,
// none; components/logging/record_policy.h) says what FILE keeps; --columns DIR extracts the
// metrics' columns of every message online (components/logging/log_columns.h). With --policy
// none there is no FILE.
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <string>

#include "components/runtime/clock.h"
#include "components/runtime/log_recorder.h"

namespace {
std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }
}  // namespace

int main(int argc, char** argv) {
  std::string url, policy = "full";
  dmpl::RecordOptions options;
  bool single_bus = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--lcm-url" && i + 1 < argc) {
      url = argv[++i];
    } else if (arg == "--channels" && i + 1 < argc) {
      options.channels = argv[++i];
    } else if (arg == "--policy" && i + 1 < argc) {
      policy = argv[++i];
    } else if (arg == "--columns" && i + 1 < argc) {
      options.columns_dir = argv[++i];
    } else if (arg == "--fields" && i + 1 < argc) {
      options.columns_fields = argv[++i];
    } else if (arg == "--run-id" && i + 1 < argc) {
      try {
        options.run_id = std::stoll(argv[++i]);
      } catch (const std::exception&) {
        std::fprintf(stderr, "dmpl_record: --run-id: not an integer: '%s'\n", argv[i]);
        return 2;
      }
    } else if (arg == "--single-bus") {
      single_bus = true;
    } else if (arg == "-h" || arg == "--help") {
      std::printf(
          "usage: dmpl_record [--lcm-url URL] [--channels REGEX] [--single-bus] "
          "[--policy full|analysis|none] [--columns DIR [--fields REGEX]] [--run-id N] "
          "[FILE]\n");
      return 0;
    } else if (arg.rfind("--", 0) == 0 || !options.log_path.empty()) {
      std::fprintf(stderr, "dmpl_record: unexpected argument '%s' (try --help)\n", arg.c_str());
      return 2;
    } else {
      options.log_path = arg;
    }
  }
  try {
    options.policy = dmpl::ParseRecordPolicy(policy);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dmpl_record: --policy: %s\n", e.what());
    return 2;
  }
  if (options.log_path.empty() != (options.policy == dmpl::RecordPolicy::kNone)) {
    std::fprintf(
        stderr, "dmpl_record: %s\n",
        options.log_path.empty() ? "no output FILE given" : "--policy none records no FILE");
    return 2;
  }
  const std::string file = options.log_path.empty() ? "(no log)" : options.log_path;
  dmpl::LcmBus bus(url, !single_bus);
  const std::vector<lcm::LCM*> instances = bus.All();
  if (!bus.good()) {
    std::fprintf(stderr, "dmpl_record: cannot open LCM '%s'\n", url.c_str());
    return 3;
  }
  auto drain = [&](int timeout_ms) {
    std::vector<pollfd> fds;
    for (lcm::LCM* l : instances) fds.push_back({l->getFileno(), POLLIN, 0});
    int handled = 0;
    if (poll(fds.data(), fds.size(), timeout_ms) <= 0) return 0;
    for (size_t i = 0; i < instances.size(); ++i) {
      if (!(fds[i].revents & POLLIN)) continue;
      while (instances[i]->handleTimeout(0) > 0) ++handled;
    }
    return handled;
  };
  try {
    dmpl::LogRecorder recorder(&bus, options);
    struct sigaction action {};
    action.sa_handler = OnSignal;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
    double last_flush = dmpl::MonotonicSeconds();
    while (!g_stop) {
      // Drain in batches: waking for each of a lockstep run's ~6000 messages a second would
      // take CPU time from the loop it records (LCM's queue holds what arrives meanwhile).
      if (drain(50) > 0) usleep(2000);
      if (dmpl::MonotonicSeconds() - last_flush > 0.2) {
        recorder.Flush();
        last_flush = dmpl::MonotonicSeconds();
      }
    }
    // What arrived before the stop, for at most a second: a bus that never goes quiet (another
    // run, a forger) must not keep the recorder from finishing its log.
    const double drain_until = dmpl::MonotonicSeconds() + 1.0;
    while (drain(20) > 0 && dmpl::MonotonicSeconds() < drain_until) {
    }
    recorder.Finish();
    std::fprintf(stderr,
                 "dmpl_record: %lld of %lld messages written to %s (policy %s)%s; copies sent "
                 "again %lld, of other runs %lld (not recorded)\n",
                 static_cast<long long>(recorder.written()),
                 static_cast<long long>(recorder.received()), file.c_str(), policy.c_str(),
                 recorder.failed() ? " (SOME WRITES FAILED)" : "",
                 static_cast<long long>(recorder.copies()),
                 static_cast<long long>(recorder.foreign()));
    return recorder.failed() ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dmpl_record: %s\n", e.what());
    return 2;
  }
}
