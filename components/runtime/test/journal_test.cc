// A journal gives back every entry written, and a last entry cut short by a kill is left out.
#include "components/runtime/journal.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>

namespace dmpl {
namespace {

class JournalTest : public ::testing::Test {
 protected:
  ~JournalTest() override { std::remove(path_.c_str()); }
  // One file per test: ctest runs the tests of this file in parallel processes.
  std::string path_ = ::testing::TempDir() + "dmpl_journal_test_" +
                      ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                      std::to_string(getpid()) + ".journal";
};

TEST_F(JournalTest, NoFileIsNoEntries) {
  int cut = -1;
  EXPECT_TRUE(ReadJournal(path_, &cut).empty());
  EXPECT_EQ(cut, 0);
}

TEST_F(JournalTest, GivesBackWhatWasAppendedAcrossWriters) {
  {
    JournalWriter w(path_);
    EXPECT_TRUE(w.Append('R', "abc", 3));
    EXPECT_TRUE(w.Append('L', "", 0));
  }
  JournalWriter again(path_);  // a restarted node appends to the same journal
  std::vector<uint8_t> big(70000, 0xAB);
  EXPECT_TRUE(again.Append('R', big.data(), big.size()));
  int cut = -1;
  const auto entries = ReadJournal(path_, &cut);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(cut, 0);
  EXPECT_EQ(entries[0].tag, 'R');
  EXPECT_EQ(std::string(entries[0].bytes.begin(), entries[0].bytes.end()), "abc");
  EXPECT_EQ(entries[1].tag, 'L');
  EXPECT_TRUE(entries[1].bytes.empty());
  EXPECT_EQ(entries[2].bytes, big);
}

TEST_F(JournalTest, AnEntryCutShortIsLeftOut) {
  {
    JournalWriter w(path_);
    w.Append('R', "complete", 8);
    w.Append('R', "cut short", 9);
  }
  // A kill in the middle of the last write: its last 4 bytes never reached the file.
  std::ifstream in(path_, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  data.resize(data.size() - 4);
  std::ofstream(path_, std::ios::binary | std::ios::trunc) << data;
  int cut = 0;
  const auto entries = ReadJournal(path_, &cut);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(cut, 1);
  EXPECT_EQ(std::string(entries[0].bytes.begin(), entries[0].bytes.end()), "complete");
}

TEST_F(JournalTest, AnUnwritablePlaceIsOneClearError) {
  try {
    JournalWriter w("/nonexistent-dir/x.journal");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.journal"), std::string::npos);
  }
}

}  // namespace
}  // namespace dmpl
