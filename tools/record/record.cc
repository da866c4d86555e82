// dmpl_record: records LCM traffic to an LCM log file (the format of lcm-logger and lcm.EventLog).
//
// Why not lcm-logger: a 1 kHz lockstep run puts ~20 000 messages a second on the bus, and
// lcm-logger's subscription queue (LCM's default of 30 messages) overflows whenever it is
// descheduled for a millisecond or two; it then drops messages silently. Here the queue is large,
// drops are counted and reported, and the exit code says whether the log is complete.
//
// usage: dmpl_record [--lcm-url URL] [--channels REGEX] FILE
#include <lcm/eventlog.h>
#include <sys/time.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <string>

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

int64_t NowMicros() {
  timeval tv;
  gettimeofday(&tv, nullptr);
  return static_cast<int64_t>(tv.tv_sec) * 1000000 + tv.tv_usec;
}

class Recorder {
 public:
  explicit Recorder(lcm_eventlog_t* log) : log_(log) {}
  void OnMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    lcm_eventlog_event_t event{};
    event.eventnum = count_;
    event.timestamp = rbuf->recv_utime;
    event.channellen = static_cast<int32_t>(channel.size());
    event.datalen = static_cast<int32_t>(rbuf->data_size);
    event.channel = const_cast<char*>(channel.c_str());
    event.data = rbuf->data;
    if (lcm_eventlog_write_event(log_, &event) != 0) {
      ++failed_;
      return;
    }
    ++count_;
  }
  int64_t count() const { return count_; }
  int64_t failed() const { return failed_; }

 private:
  lcm_eventlog_t* log_;
  int64_t count_ = 0;
  int64_t failed_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string url, channels = ".*", file;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--lcm-url" || arg == "--channels") && i + 1 < argc) {
      (arg == "--lcm-url" ? url : channels) = argv[++i];
    } else if (arg == "-h" || arg == "--help") {
      std::printf("usage: dmpl_record [--lcm-url URL] [--channels REGEX] FILE\n");
      return 0;
    } else if (arg.rfind("--", 0) == 0 || !file.empty()) {
      std::fprintf(stderr, "dmpl_record: unexpected argument '%s' (try --help)\n", arg.c_str());
      return 2;
    } else {
      file = arg;
    }
  }
  if (file.empty()) {
    std::fprintf(stderr, "dmpl_record: no output FILE given\n");
    return 2;
  }
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "dmpl_record: cannot open LCM '%s'\n", url.c_str());
    return 3;
  }
  lcm_eventlog_t* log = lcm_eventlog_create(file.c_str(), "w");
  if (log == nullptr) {
    std::fprintf(stderr, "dmpl_record: cannot create '%s': %s\n", file.c_str(), std::strerror(errno));
    return 2;
  }
  Recorder recorder(log);
  lcm::Subscription* sub = lcm.subscribe(channels, &Recorder::OnMessage, &recorder);
  sub->setQueueCapacity(1 << 20);
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  int64_t last_flush = NowMicros();
  while (!g_stop) {
    lcm.handleTimeout(50);
    if (NowMicros() - last_flush > 200000) {
      fflush(log->f);
      last_flush = NowMicros();
    }
  }
  // Drain what arrived before the stop.
  while (lcm.handleTimeout(20) > 0) {
  }
  lcm.unsubscribe(sub);
  lcm_eventlog_destroy(log);
  std::fprintf(stderr, "dmpl_record: %lld messages written to %s%s\n",
               static_cast<long long>(recorder.count()), file.c_str(),
               recorder.failed() ? " (SOME WRITES FAILED)" : "");
  return recorder.failed() ? 1 : 0;
}
