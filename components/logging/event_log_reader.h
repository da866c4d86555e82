#pragma once
// Reads an LCM event log (the format of lcm-logger, lcm.EventLog and dmpl_record) in one pass,
// robustly: bytes that are not an event (garbage, a torn write) are skipped up to the next event
// and counted, and a truncated last event ends the log instead of failing it. Each event is a
// 28-byte big-endian header (sync word 0xEDA1DA01, event number, utime, channel length, data
// length), the channel name, then the payload.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace dmpl {

struct LogEvent {
  int64_t eventnum = 0;
  int64_t timestamp = 0;  // the receive time, microseconds
  std::string_view channel;
  const uint8_t* data = nullptr;
  size_t size = 0;
};

class EventLogReader {
 public:
  // Maps the file. Throws std::runtime_error naming the file when it cannot be read.
  explicit EventLogReader(const std::string& path);
  ~EventLogReader();
  EventLogReader(const EventLogReader&) = delete;
  EventLogReader& operator=(const EventLogReader&) = delete;

  // The next event, or false at the end of the log. The event's views stay valid until the next
  // call.
  bool Next(LogEvent* event);

  int64_t skipped_bytes() const { return skipped_bytes_; }  // bytes that were not an event
  int64_t resyncs() const { return resyncs_; }              // places where they were skipped
  bool truncated() const { return truncated_; }             // the last event was incomplete
  size_t file_size() const { return size_; }

 private:
  bool EventAt(size_t pos, LogEvent* event, size_t* end) const;

  const uint8_t* base_ = nullptr;
  size_t size_ = 0;
  size_t pos_ = 0;
  size_t released_ = 0;  // pages before this offset were given back
  int64_t skipped_bytes_ = 0;
  int64_t resyncs_ = 0;
  bool truncated_ = false;
};

}  // namespace dmpl
