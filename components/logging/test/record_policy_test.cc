#include "components/logging/record_policy.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "components/logging/message_layout.h"
#include "components/runtime/channels.h"
#include "dmpl/hand_sensors_t.hpp"

namespace dmpl {
namespace {

// A dmpl-like message: fingerprint, utime, seq (big-endian), then a payload byte.
std::vector<uint8_t> Message(int64_t seq, uint8_t payload = 0) {
  std::vector<uint8_t> m(25, 0);
  for (int i = 0; i < 8; ++i) m[16 + i] = static_cast<uint8_t>(seq >> (56 - 8 * i));
  m[8] = static_cast<uint8_t>(seq);  // utime changes with the tick too
  m[24] = payload;
  return m;
}

// A tick's sensors with one fingertip at `force` (no contact when negative).
std::vector<uint8_t> Sensors(int64_t seq, double force) {
  hand_sensors_t m{};
  m.utime = seq * 1000;
  m.seq = seq;
  m.tactile.num_fingers = 1;
  m.tactile.fingers.resize(1);
  m.tactile.fingers[0].finger = "T";
  m.tactile.fingers[0].in_contact = force >= 0;
  m.tactile.fingers[0].force_n = force < 0 ? 0.0 : force;
  std::vector<uint8_t> out(m.getEncodedSize());
  m.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

int Kept(RecordFilter* f, const char* channel, int64_t from, int64_t to) {
  int kept = 0;
  for (int64_t s = from; s < to; ++s) {
    const auto m = Message(s);
    kept += f->Keep(channel, m.data(), m.size());
  }
  return kept;
}

TEST(RecordPolicyTest, ParsesTheThreeNamesAndRejectsOthers) {
  EXPECT_EQ(ParseRecordPolicy("full"), RecordPolicy::kFull);
  EXPECT_EQ(ParseRecordPolicy("analysis"), RecordPolicy::kAnalysis);
  EXPECT_EQ(ParseRecordPolicy("none"), RecordPolicy::kNone);
  EXPECT_THROW(ParseRecordPolicy("Full"), std::invalid_argument);
}

TEST(RecordPolicyTest, SeqIsReadFromTheMessageBytes) {
  const auto m = Message(123456789);
  EXPECT_EQ(SeqOf(m.data(), m.size()), 123456789);
  EXPECT_EQ(SeqOf(m.data(), 23), -1);
  EXPECT_EQ(RunIdOf(m.data(), m.size()), 0);  // a type without a run
  // A type of the loop carries its run first, then utime and seq.
  hand_sensors_t s{};
  s.run_id = 77;
  s.seq = 4242;
  std::vector<uint8_t> bytes(static_cast<size_t>(s.getEncodedSize()));
  s.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  EXPECT_TRUE(CarriesRunId(bytes.data(), bytes.size()));
  EXPECT_EQ(RunIdOf(bytes.data(), bytes.size()), 77);
  EXPECT_EQ(SeqOf(bytes.data(), bytes.size()), 4242);
  EXPECT_EQ(HeaderSize(bytes.data(), bytes.size()), 32u);
}

TEST(RecordPolicyTest, FullKeepsEverythingAndNoneNothing) {
  RecordFilter full(RecordPolicy::kFull), none(RecordPolicy::kNone);
  EXPECT_EQ(Kept(&full, channels::kJointCmd, 0, 1000), 1000);
  EXPECT_EQ(Kept(&none, channels::kSimControl, 0, 1000), 0);
}

TEST(RecordPolicyTest, AnalysisThinsTheTickChannelsByTheirRates) {
  RecordFilter f(RecordPolicy::kAnalysis);
  EXPECT_EQ(Kept(&f, channels::kSensors, 0, 2000), 100);            // 50 Hz
  EXPECT_EQ(Kept(&f, channels::kControllerStatus, 0, 2000), 200);   // 2 bursts of 100 ticks
  EXPECT_EQ(Kept(&f, channels::kControllerStatus, 950, 1050), 50);  // consecutive from 1000
  EXPECT_EQ(Kept(&f, channels::kControllerReport, 0, 200), 200);
  EXPECT_EQ(Kept(&f, channels::kJointCmd, 0, 100), 0);
  EXPECT_EQ(Kept(&f, channels::kFingerTargets, 0, 100), 0);
  EXPECT_EQ(Kept(&f, "SOMEONE_ELSES_CHANNEL", 0, 100), 100);
}

TEST(RecordPolicyTest, AnalysisKeepsTheTruthAt100HzAndAtEveryTouchEvent) {
  RecordFilter f(RecordPolicy::kAnalysis);
  std::vector<int64_t> kept;
  for (int64_t s = 0; s < 100; ++s) {
    // A steady 0.8 N grip, a 3 N impact over ticks 33-35, contact lost over 61-64.
    double force = 0.8 + 0.01 * static_cast<double>(s % 3);
    if (s >= 33 && s <= 35) force = 3.0;
    if (s >= 61 && s <= 64) force = -1.0;
    const auto m = Sensors(s, force);
    if (f.Keep(channels::kSensorsTrue, m.data(), m.size())) kept.push_back(s);
  }
  EXPECT_EQ(kept, (std::vector<int64_t>{0, 10, 20, 30, 33, 36, 40, 50, 60, 61, 65, 70, 80, 90}));
}

TEST(RecordPolicyTest, AnalysisKeepsATaskOnlyWhenItChanges) {
  RecordFilter f(RecordPolicy::kAnalysis);
  int kept = 0;
  for (int64_t s = 0; s < 100; ++s) {
    const auto m = Message(s, static_cast<uint8_t>(s / 30));  // a new task every 30 ticks
    kept += f.Keep(channels::kTask, m.data(), m.size());
  }
  EXPECT_EQ(kept, 4);
}

}  // namespace
}  // namespace dmpl
