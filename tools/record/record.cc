// dmpl_record: records LCM traffic to an LCM log file (the format of lcm-logger and lcm.EventLog).
//
// Why not lcm-logger: a 1 kHz lockstep run puts ~20 000 messages a second on the bus, and
// lcm-logger's subscription queue (LCM's default of 30 messages) overflows whenever it is
// descheduled for a millisecond or two; it then drops messages silently. Here the queue is large,
// and the exit code says whether every write succeeded.
//
// usage: dmpl_record [--lcm-url URL] [--channels REGEX] [--single-bus] [--policy P]
//                    [--columns DIR [--fields REGEX]] [--run-id N] [FILE]
// --run-id N: messages of another run (Node::OfThisRun's rule) are neither logged nor extracted.
// Every bus of the URL is recorded (channels.h), unless --single-bus. --policy (full, analysis,
// none; components/logging/record_policy.h) says what FILE keeps; --columns DIR extracts the
// metrics' columns of every message online (components/logging/log_columns.h). With --policy
// none there is no FILE.
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "components/runtime/clock.h"
#include "components/runtime/command_line.h"
#include "components/runtime/log_recorder.h"

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

struct CommandLine {
  std::string url;
  std::string policy = "full";
  dmpl::RecordOptions options;
  bool single_bus = false;
};

// Parses the command line into `cl`; the exit code when the process is to exit now.
std::optional<int> ParseCommandLine(int argc, char** argv, CommandLine* cl) {
  CLI::App app{"dmpl_record: records LCM traffic to an LCM log file", "dmpl_record"};
  app.add_option("FILE", cl->options.log_path, "the log written (none with --policy none)");
  app.add_option("--lcm-url", cl->url, "the LCM URL to record (default: $LCM_DEFAULT_URL)")
      ->type_name("URL");
  app.add_option("--channels", cl->options.channels, "the channels recorded (a regex; default all)")
      ->type_name("REGEX");
  app.add_flag("--single-bus", cl->single_bus, "record the URL's own bus only, not buses 1-9");
  app.add_option("--policy", cl->policy, "what FILE keeps: full, analysis or none (default full)")
      ->type_name("POLICY");
  app.add_option("--columns", cl->options.columns_dir,
                 "extract the metrics' columns of every message online into DIR")
      ->type_name("DIR");
  app.add_option("--fields", cl->options.columns_fields,
                 "the fields extracted with --columns, as CHANNEL/name (a regex)")
      ->type_name("REGEX");
  app.add_option("--run-id", cl->options.run_id,
                 "record only this run's messages (and those of no run)")
      ->type_name("N");
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return code;
  try {
    cl->options.policy = dmpl::ParseRecordPolicy(cl->policy);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dmpl_record: --policy: %s\n", e.what());
    return 2;
  }
  if (cl->options.log_path.empty() != (cl->options.policy == dmpl::RecordPolicy::kNone)) {
    std::fprintf(
        stderr, "dmpl_record: %s\n",
        cl->options.log_path.empty() ? "no output FILE given" : "--policy none records no FILE");
    return 2;
  }
  return std::nullopt;
}

// Handles what is queued on any bus, waiting up to `timeout_ms` for something; how many it handled.
int Drain(const std::vector<lcm::LCM*>& instances, int timeout_ms) {
  std::vector<pollfd> fds;
  for (lcm::LCM* l : instances) fds.push_back({l->getFileno(), POLLIN, 0});
  int handled = 0;
  if (poll(fds.data(), fds.size(), timeout_ms) <= 0) return 0;
  for (size_t i = 0; i < instances.size(); ++i) {
    if (!(fds[i].revents & POLLIN)) continue;
    while (instances[i]->handleTimeout(0) > 0) ++handled;
  }
  return handled;
}

// Records until SIGINT or SIGTERM, then what arrived before it; the exit code.
int Record(dmpl::LcmBus* bus, const CommandLine& cl) {
  const std::vector<lcm::LCM*> instances = bus->All();
  dmpl::LogRecorder recorder(bus, cl.options);
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  double last_flush = dmpl::MonotonicSeconds();
  while (!g_stop) {
    // Drain in batches: waking for each of a lockstep run's ~6000 messages a second would
    // take CPU time from the loop it records (LCM's queue holds what arrives meanwhile).
    if (Drain(instances, 50) > 0) usleep(2000);
    if (dmpl::MonotonicSeconds() - last_flush > 0.2) {
      recorder.Flush();
      last_flush = dmpl::MonotonicSeconds();
    }
  }
  // What arrived before the stop, for at most a second: a bus that never goes quiet (another
  // run, a forger) must not keep the recorder from finishing its log.
  const double drain_until = dmpl::MonotonicSeconds() + 1.0;
  while (Drain(instances, 20) > 0 && dmpl::MonotonicSeconds() < drain_until) {
  }
  recorder.Finish();
  const std::string file = cl.options.log_path.empty() ? "(no log)" : cl.options.log_path;
  std::fprintf(stderr,
               "dmpl_record: %lld of %lld messages written to %s (policy %s)%s; copies sent "
               "again %lld, of other runs %lld (not recorded); asked again %lld\n",
               static_cast<long long>(recorder.written()),
               static_cast<long long>(recorder.received()), file.c_str(), cl.policy.c_str(),
               recorder.failed() ? " (SOME WRITES FAILED)" : "",
               static_cast<long long>(recorder.copies()),
               static_cast<long long>(recorder.foreign()),
               static_cast<long long>(recorder.asked_again()));
  return recorder.failed() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CommandLine cl;
  if (const auto code = ParseCommandLine(argc, argv, &cl)) return *code;
  dmpl::LcmBus bus(cl.url, !cl.single_bus);
  if (!bus.good()) {
    std::fprintf(stderr, "dmpl_record: cannot open LCM '%s'\n", cl.url.c_str());
    return 3;
  }
  try {
    return Record(&bus, cl);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dmpl_record: %s\n", e.what());
    return 2;
  }
}
