// dmpl_logcols: one pass over an LCM log -> the column files of the channels tools read
// (components/logging/log_columns.h), for numpy. Undecodable messages, garbage between events
// and a truncated last event are counted in DIR/meta.json; they never stop the pass.
//
// usage: dmpl_logcols LOG DIR [--channels REGEX] [--fields REGEX]   (a field: CHANNEL/name)
#include <cstdio>
#include <string>

#include "components/logging/event_log_reader.h"
#include "components/logging/log_columns.h"

int main(int argc, char** argv) {
  std::string log_path, dir, channels = ".*", fields = ".*";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--channels" && i + 1 < argc) {
      channels = argv[++i];
    } else if (arg == "--fields" && i + 1 < argc) {
      fields = argv[++i];
    } else if (arg == "-h" || arg == "--help") {
      std::printf("usage: dmpl_logcols LOG DIR [--channels REGEX] [--fields REGEX]\n");
      return 0;
    } else if (arg.rfind("--", 0) == 0) {
      std::fprintf(stderr, "dmpl_logcols: unexpected argument '%s' (try --help)\n", arg.c_str());
      return 2;
    } else if (log_path.empty()) {
      log_path = arg;
    } else if (dir.empty()) {
      dir = arg;
    } else {
      std::fprintf(stderr, "dmpl_logcols: too many arguments (try --help)\n");
      return 2;
    }
  }
  if (dir.empty()) {
    std::fprintf(stderr, "dmpl_logcols: expected LOG and DIR (try --help)\n");
    return 2;
  }
  try {
    dmpl::EventLogReader reader(log_path);
    dmpl::LogColumns columns(dir, channels, fields);
    dmpl::LogEvent e;
    int64_t events = 0, first = 0, last = 0;
    while (reader.Next(&e)) {
      if (events++ == 0) first = e.timestamp;
      last = e.timestamp;
      columns.Add(e.channel, e.data, e.size);
    }
    columns.Finish("\"source\": {\"events\": " + std::to_string(events) +
                   ", \"bytes\": " + std::to_string(reader.file_size()) +
                   ", \"skipped_bytes\": " + std::to_string(reader.skipped_bytes()) +
                   ", \"resyncs\": " + std::to_string(reader.resyncs()) +
                   ", \"truncated\": " + (reader.truncated() ? "true" : "false") +
                   ", \"first_timestamp\": " + std::to_string(first) +
                   ", \"last_timestamp\": " + std::to_string(last) + "}");
    if (reader.skipped_bytes() > 0 || reader.truncated() || columns.rejected() > 0) {
      std::fprintf(stderr,
                   "dmpl_logcols: %s: %lld bytes of garbage skipped, %lld messages rejected%s\n",
                   log_path.c_str(), static_cast<long long>(reader.skipped_bytes()),
                   static_cast<long long>(columns.rejected()),
                   reader.truncated() ? ", the last event is truncated" : "");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dmpl_logcols: %s\n", e.what());
    return 1;
  }
  return 0;
}
