// dmpl_logcols: one pass over an LCM log -> the column files of the channels tools read
// (components/logging/log_columns.h), for numpy. Undecodable messages, garbage between events
// and a truncated last event are counted in DIR/meta.json; they never stop the pass.
//
// usage: dmpl_logcols LOG DIR [--channels REGEX] [--fields REGEX]   (a field: CHANNEL/name)
#include <cstdio>
#include <string>

#include "components/logging/event_log_reader.h"
#include "components/logging/log_columns.h"
#include "components/runtime/command_line.h"

int main(int argc, char** argv) {
  CLI::App app{"dmpl_logcols: one pass over an LCM log -> the column files of its channels",
               "dmpl_logcols"};
  std::string log_path, dir, channels = ".*", fields = ".*";
  app.add_option("LOG", log_path, "the LCM log to read")->required();
  app.add_option("DIR", dir, "where the column files and meta.json go")->required();
  app.add_option("--channels", channels, "the channels to extract (a regex; default all)")
      ->type_name("REGEX");
  app.add_option("--fields", fields, "the fields to extract, as CHANNEL/name (a regex; default "
                                     "all)")
      ->type_name("REGEX");
  if (const auto code = dmpl::ParseCommandLine(app, argc, argv)) return *code;
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
  } catch (const std::exception& e) {  // a log it cannot read, a directory it cannot write
    std::fprintf(stderr, "dmpl_logcols: %s\n", e.what());
    return 2;
  }
  return 0;
}
