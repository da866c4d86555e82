#include "components/logging/log_columns.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "components/runtime/channels.h"
#include "dmpl/hand_sensors_t.hpp"
#include "dmpl/sim_control_t.hpp"

namespace dmpl {
namespace {
namespace fs = std::filesystem;

hand_sensors_t Sensors(int64_t seq, int fingers = 4) {
  hand_sensors_t m{};
  m.utime = seq * 1000;
  m.seq = seq;
  m.object.valid = 1;
  m.object.position[0] = 0.07 + 1e-6 * static_cast<double>(seq);
  m.object.orientation[0] = 1.0;
  m.joints.num_joints = 2;
  m.joints.name = {"a", "b"};
  m.joints.position = {0.1 * static_cast<double>(seq), 0.2};
  m.joints.velocity = {0.0, 0.0};
  m.joints.effort = {0.0, 0.0};
  m.tactile.num_fingers = static_cast<int8_t>(fingers);
  const char* names[] = {"T", "F", "M", "R"};
  for (int f = 0; f < fingers; ++f) {
    fingertip_contact_t c{};
    c.finger = names[f];
    c.in_contact = f % 2;
    c.force_n = f + 0.5;
    m.tactile.fingers.push_back(c);
  }
  return m;
}

template <typename Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> out(m.getEncodedSize());
  m.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

// The data of an .npy written by NpyColumn: the header is 128 bytes.
std::vector<char> NpyData(const std::string& path, std::string* header) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> all{std::istreambuf_iterator<char>(in), {}};
  *header = std::string(all.begin() + 10, all.begin() + 128);
  return {all.begin() + 128, all.end()};
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(LogColumnsTest, WritesOneRowPerMessageAndSkipsWhatItCannotDecode) {
  const std::string dir =
      (fs::temp_directory_path() / ("dmpl_cols_" + std::to_string(getpid()))).string();
  {
    LogColumns cols(dir);
    for (int64_t s = 0; s < 10; ++s) {
      const auto bytes = Encode(Sensors(s));
      EXPECT_TRUE(cols.Add(channels::kSensorsTrue, bytes.data(), bytes.size()));
    }
    // Random bytes, a truncated message, another type, another finger count: skipped, counted.
    std::vector<uint8_t> junk(300, 0x5a);
    EXPECT_FALSE(cols.Add(channels::kSensorsTrue, junk.data(), junk.size()));
    auto good = Encode(Sensors(10));
    EXPECT_FALSE(cols.Add(channels::kSensorsTrue, good.data(), good.size() / 2));
    sim_control_t control{};
    control.command = sim_control_t::RELEASE;
    const auto other = Encode(control);
    EXPECT_FALSE(cols.Add(channels::kSensorsTrue, other.data(), other.size()));
    const auto three = Encode(Sensors(11, 3));
    EXPECT_FALSE(cols.Add(channels::kSensorsTrue, three.data(), three.size()));
    EXPECT_TRUE(cols.Add(channels::kSimControl, other.data(), other.size()));
    EXPECT_TRUE(cols.Add("UNKNOWN", junk.data(), junk.size()));
    EXPECT_EQ(cols.rejected(), 4);
    cols.Finish("\"test\": true");
  }
  std::string header;
  const auto seq = NpyData(dir + "/DMPL_SENSORS_TRUE/seq.npy", &header);
  EXPECT_NE(header.find("'shape': (10,)"), std::string::npos) << header;
  ASSERT_EQ(seq.size(), 10 * sizeof(int64_t));
  int64_t last = 0;
  std::memcpy(&last, seq.data() + 9 * sizeof(int64_t), sizeof(last));
  EXPECT_EQ(last, 9);
  const auto pos = NpyData(dir + "/DMPL_SENSORS_TRUE/object_position.npy", &header);
  EXPECT_NE(header.find("'shape': (10, 3)"), std::string::npos) << header;
  double x = 0;
  std::memcpy(&x, pos.data() + 9 * 3 * sizeof(double), sizeof(x));
  EXPECT_DOUBLE_EQ(x, 0.07 + 9e-6);
  NpyData(dir + "/DMPL_SENSORS_TRUE/tactile_force.npy", &header);
  EXPECT_NE(header.find("'shape': (10, 4)"), std::string::npos) << header;
  const std::string meta = ReadText(dir + "/meta.json");
  EXPECT_NE(meta.find("\"cannot decode as hand_sensors_t\": 3"), std::string::npos) << meta;
  EXPECT_NE(meta.find("\"fingers differ from the first message's\": 1"), std::string::npos);
  EXPECT_NE(meta.find("\"UNKNOWN\": 1"), std::string::npos);
  EXPECT_NE(meta.find("\"test\": true"), std::string::npos);
  fs::remove_all(dir);
}

TEST(LogColumnsTest, AChannelWithNoFieldAskedForIsCountedNotDecoded) {
  const std::string dir =
      (fs::temp_directory_path() / ("dmpl_cols_skip_" + std::to_string(getpid()))).string();
  {
    LogColumns cols(dir, ".*", "^DMPL_SENSORS_TRUE/(seq)$");
    const auto bytes = Encode(Sensors(1));
    std::vector<uint8_t> junk(300, 0x5a);
    for (const char* channel : {channels::kSensorsTrue, channels::kSensors}) {
      EXPECT_TRUE(cols.Add(channel, bytes.data(), bytes.size()));
      EXPECT_TRUE(cols.Add(channel, bytes.data(), bytes.size()));
    }
    // Garbage on the channel that is asked for is still caught; on the other, not decoded.
    EXPECT_FALSE(cols.Add(channels::kSensorsTrue, junk.data(), junk.size()));
    EXPECT_TRUE(cols.Add(channels::kSensors, junk.data(), junk.size()));
    cols.Finish();
  }
  const std::string meta = ReadText(dir + "/meta.json");
  EXPECT_NE(meta.find("\"DMPL_SENSORS\": {\"type\": \"hand_sensors_t\", \"messages\": 3, "
                      "\"rows\": 0"),
            std::string::npos)
      << meta;
  EXPECT_TRUE(fs::exists(dir + "/DMPL_SENSORS_TRUE/seq.npy"));
  EXPECT_FALSE(fs::exists(dir + "/DMPL_SENSORS_TRUE/object_position.npy"));
  EXPECT_FALSE(fs::exists(dir + "/DMPL_SENSORS"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dmpl
