#include "components/logging/event_log_reader.h"

#include <gtest/gtest.h>
#include <lcm/eventlog.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace dmpl {
namespace {

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("dmpl_" + name + "_" + std::to_string(::getpid())))
      .string();
}

// Writes events with LCM's own writer, so the reader is checked against the real format.
void WriteLog(const std::string& path, int n) {
  lcm_eventlog_t* log = lcm_eventlog_create(path.c_str(), "w");
  ASSERT_NE(log, nullptr);
  for (int i = 0; i < n; ++i) {
    std::string channel = "CH" + std::to_string(i % 3);
    std::vector<uint8_t> data(10 + i, static_cast<uint8_t>(i));
    lcm_eventlog_event_t e{};
    e.timestamp = 1000 + i;
    e.channellen = static_cast<int32_t>(channel.size());
    e.datalen = static_cast<int32_t>(data.size());
    e.channel = channel.data();
    e.data = data.data();
    ASSERT_EQ(lcm_eventlog_write_event(log, &e), 0);
  }
  lcm_eventlog_destroy(log);
}

std::vector<char> ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void WriteAll(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Reads every event, checking each against what WriteLog wrote; returns how many.
int Count(EventLogReader* r) {
  LogEvent e;
  int n = 0;
  while (r->Next(&e)) {
    EXPECT_EQ(e.size, static_cast<size_t>(10 + e.timestamp - 1000));
    EXPECT_EQ(e.channel, "CH" + std::to_string((e.timestamp - 1000) % 3));
    ++n;
  }
  return n;
}

TEST(EventLogReaderTest, ReadsEveryEventOfAnLcmLog) {
  const std::string path = TempPath("clean");
  WriteLog(path, 50);
  EventLogReader r(path);
  EXPECT_EQ(Count(&r), 50);
  EXPECT_EQ(r.skipped_bytes(), 0);
  EXPECT_FALSE(r.truncated());
  std::remove(path.c_str());
}

TEST(EventLogReaderTest, ATruncatedLastEventEndsTheLog) {
  const std::string path = TempPath("truncated");
  WriteLog(path, 50);
  auto bytes = ReadAll(path);
  bytes.resize(bytes.size() - 20);  // into the payload of the last event
  WriteAll(path, bytes);
  EventLogReader r(path);
  EXPECT_EQ(Count(&r), 49);
  EXPECT_TRUE(r.truncated());
  std::remove(path.c_str());
}

TEST(EventLogReaderTest, GarbageBetweenEventsIsSkippedAndCounted) {
  const std::string path = TempPath("garbage");
  WriteLog(path, 50);
  auto bytes = ReadAll(path);
  // 37 bytes of junk (with a fake sync word) after the first event (28 + 3 + 10 bytes).
  std::vector<char> junk(37, 'x');
  junk[5] = static_cast<char>(0xED), junk[6] = static_cast<char>(0xA1);
  junk[7] = static_cast<char>(0xDA), junk[8] = 1;
  bytes.insert(bytes.begin() + 41, junk.begin(), junk.end());
  WriteAll(path, bytes);
  EventLogReader r(path);
  EXPECT_EQ(Count(&r), 50);
  EXPECT_EQ(r.skipped_bytes(), 37);
  EXPECT_EQ(r.resyncs(), 1);
  std::remove(path.c_str());
}

TEST(EventLogReaderTest, AMissingFileIsAClearError) {
  try {
    EventLogReader r("/nonexistent/run.lcmlog");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/run.lcmlog"), std::string::npos);
  }
}

}  // namespace
}  // namespace dmpl
