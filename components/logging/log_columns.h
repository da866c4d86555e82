#pragma once
// Turns dmpl messages into column files (one NumPy .npy per field) that tools load as arrays:
// one table per channel, rows in the order the messages came, strings as codes into tables kept
// in meta.json. Used on a recorded log (dmpl_logcols) and online by the recorder, which sees
// every message whatever the record policy keeps, so that metrics never need the log.
//
//   DIR/meta.json                 per channel: type, rows, rejected messages (by reason),
//                                 fingers, joints, string tables; other channels' counts
//   DIR/<CHANNEL>/<field>.npy     e.g. DMPL_SENSORS_TRUE/object_position.npy, shape (rows, 3)
//   DIR/<CHANNEL>/events/*.npy    controller events (utime, seq, type, finger, value, text)
//
// A channel none of whose fields is asked for is counted but not decoded after its first message.
// A message that cannot be decoded (random bytes, a truncated message, another type on a known
// channel) or whose layout differs from the channel's first row (another finger count) is
// skipped and counted with its reason; it never stops the rest.
#include <cstdint>
#include <map>
#include <memory>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include "components/logging/npy_writer.h"

namespace dmpl {

class LogColumns {
 public:
  // Writes under `dir` (created) the channels it knows that match `channels`, and of them the
  // fields that match `fields` (regexes; a field is named CHANNEL/field, an event's field
  // CHANNEL/events/field).
  explicit LogColumns(const std::string& dir, const std::string& channels = ".*",
                      const std::string& fields = ".*");
  ~LogColumns();
  LogColumns(const LogColumns&) = delete;
  LogColumns& operator=(const LogColumns&) = delete;

  // One message as it was received. Returns false when it was skipped as undecodable.
  bool Add(std::string_view channel, const uint8_t* data, size_t size);

  // Closes every column and writes meta.json; `extra` holds more JSON members for its top level
  // (e.g. `"truncated": false`), without braces. Throws std::runtime_error on I/O errors.
  void Finish(const std::string& extra = "");

  int64_t rejected() const { return rejected_; }

  // The table of a channel (exposed for tests and tools).
  class Table;
  struct Channel;

 private:
  Channel* ChannelFor(std::string_view name);
  bool WantsEvents(const std::string& channel) const;
  std::string dir_;
  std::regex channels_, fields_;
  std::map<std::string, std::unique_ptr<Channel>, std::less<>> known_;
  std::map<std::string, int64_t, std::less<>> others_;  // messages of channels without columns
  int64_t rejected_ = 0;
  bool finished_ = false;
};

// The column type of each known channel ("" when it has none).
std::string ColumnTypeOf(std::string_view channel);

}  // namespace dmpl
