// The recorder asks again for exactly what it lost, and a publisher knows when all it sent is
// recorded (record_confirm.h).
#include "components/runtime/record_confirm.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace dmpl {
namespace {

std::vector<uint8_t> Bytes(int64_t seq, int part = 0) {
  return {static_cast<uint8_t>(seq), static_cast<uint8_t>(seq >> 8), static_cast<uint8_t>(part)};
}

void Record(ReceivedRecord* rec, const std::string& channel, int64_t seq, int part = 0) {
  const auto bytes = Bytes(seq, part);
  rec->Add(channel, seq, HashBytes(bytes.data(), bytes.size()));
}

// Delivers every ledger entry to the recorder and its receipts back, as the bus would without
// loss; returns the messages sent again.
std::vector<std::vector<uint8_t>> Exchange(PublishedRecord* pub, ReceivedRecord* rec,
                                           const std::string& channel) {
  std::vector<std::vector<uint8_t>> again;
  for (const LedgerEntry& e : pub->Ledger()) {
    for (const auto* bytes : pub->Confirm(rec->Answer(e))) {
      again.push_back(*bytes);
      rec->Add(channel, (*bytes)[0] | ((*bytes)[1] << 8), HashBytes(bytes->data(), bytes->size()));
    }
  }
  return again;
}

TEST(RecordConfirmTest, NothingLostIsConfirmedAtOnce) {
  PublishedRecord pub(100);
  ReceivedRecord rec;
  for (int64_t seq = 0; seq < 50; ++seq) {
    pub.Add("A", seq, Bytes(seq));
    Record(&rec, "A", seq);
  }
  EXPECT_FALSE(pub.AllConfirmed());
  EXPECT_TRUE(Exchange(&pub, &rec, "A").empty());
  EXPECT_TRUE(pub.AllConfirmed());
  EXPECT_TRUE(pub.heard_recorder());
  EXPECT_TRUE(pub.Ledger().empty());
}

TEST(RecordConfirmTest, SendsAgainExactlyTheLostOnesIncludingTheLast) {
  PublishedRecord pub(1000);
  ReceivedRecord rec;
  std::mt19937 rng(3);
  std::set<int64_t> lost;
  for (int64_t seq = 10; seq < 400; seq += 10) {  // a channel published every 10 ticks
    pub.Add("S", seq, Bytes(seq));
    if (rng() % 5 == 0 || seq == 390) {
      lost.insert(seq);  // the last one too: nothing after it would show the gap
    } else {
      Record(&rec, "S", seq);
    }
  }
  std::set<int64_t> again;
  for (const auto& b : Exchange(&pub, &rec, "S")) again.insert(b[0] | (b[1] << 8));
  EXPECT_EQ(again, lost);
  EXPECT_FALSE(pub.AllConfirmed());  // the receipt asked; the next ledger confirms
  EXPECT_TRUE(Exchange(&pub, &rec, "S").empty());
  EXPECT_TRUE(pub.AllConfirmed());
}

TEST(RecordConfirmTest, SeveralMessagesOfOneSeq) {
  PublishedRecord pub(100);
  ReceivedRecord rec;
  pub.Add("C", 5, Bytes(5, 0));
  pub.Add("C", 5, Bytes(5, 1));
  pub.Add("C", 6, Bytes(6, 0));
  Record(&rec, "C", 5);  // the first of tick 5 arrived, its second and tick 6 were lost
  const auto again = Exchange(&pub, &rec, "C");
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[0], Bytes(5, 1));
  EXPECT_EQ(again[1], Bytes(6, 0));
}

TEST(RecordConfirmTest, TheSameBytesPublishedTwiceAreOneMessage) {
  PublishedRecord pub(100);
  ReceivedRecord rec;
  pub.Add("S", 9, Bytes(9));
  pub.Add("S", 9, Bytes(9));  // a status published again unchanged: the recorder keeps one
  Record(&rec, "S", 9);
  EXPECT_TRUE(Exchange(&pub, &rec, "S").empty());
  EXPECT_TRUE(pub.AllConfirmed());
}

TEST(RecordConfirmTest, AFirstMessageLostIsAskedFor) {
  PublishedRecord pub(100);
  ReceivedRecord rec;
  for (int64_t seq = 0; seq < 5; ++seq) pub.Add("T", seq, Bytes(seq));
  for (int64_t seq = 1; seq < 5; ++seq) Record(&rec, "T", seq);  // tick 0 lost
  const auto again = Exchange(&pub, &rec, "T");
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0], Bytes(0));
  EXPECT_TRUE(Exchange(&pub, &rec, "T").empty());
  EXPECT_TRUE(pub.AllConfirmed());
}

TEST(RecordConfirmTest, WithoutARecorderOnlyTheLatestAreKept) {
  PublishedRecord pub(8);
  for (int64_t seq = 0; seq < 100; ++seq) pub.Add("A", seq, Bytes(seq));
  const auto ledger = pub.Ledger();
  ASSERT_EQ(ledger.size(), 1u);
  EXPECT_EQ(ledger[0].after_seq, 91);
  EXPECT_EQ(ledger[0].through_seq, 99);
  EXPECT_EQ(ledger[0].count, 8);
  EXPECT_EQ(pub.dropped_unconfirmed(), 92);
  EXPECT_FALSE(pub.heard_recorder());
}

TEST(RecordConfirmTest, ALedgerOlderThanTheWindowIsNotAskedFor) {
  ReceivedRecord rec(100);
  for (int64_t seq = 0; seq < 1000; ++seq) Record(&rec, "A", seq);
  EXPECT_TRUE(rec.Answer({"A", 10, 20, 50}).complete);   // before the window: cannot check
  EXPECT_FALSE(rec.Answer({"A", 950, 999, 50}).complete);  // 49 recorded, 50 published
  EXPECT_TRUE(rec.Answer({"A", 949, 999, 50}).complete);
  Record(&rec, "A", 1'000'000'000);  // a forged seq far ahead does not move the window
  EXPECT_FALSE(rec.Answer({"A", 950, 999, 50}).complete);
}

TEST(RecordConfirmTest, TellsACopyFromANewMessageLongAfter) {
  ReceivedRecord rec;
  const auto first = Bytes(7, 0), second = Bytes(7, 1);
  EXPECT_EQ(rec.Add("A", 7, HashBytes(first.data(), 3)), ReceivedRecord::Verdict::kNew);
  for (int64_t seq = 8; seq < 5000; ++seq) Record(&rec, "A", seq);  // far more than 512 later
  EXPECT_EQ(rec.Add("A", 7, HashBytes(first.data(), 3)), ReceivedRecord::Verdict::kCopy);
  EXPECT_EQ(rec.Add("A", 7, HashBytes(second.data(), 3)), ReceivedRecord::Verdict::kNew);
  EXPECT_EQ(rec.Add("A", 7, HashBytes(second.data(), 3)), ReceivedRecord::Verdict::kCopy);
  EXPECT_EQ(rec.Add("A", -1, 1), ReceivedRecord::Verdict::kUnknown);
  EXPECT_EQ(rec.newest("A"), 4999);
  EXPECT_EQ(rec.newest("B"), -1);
}

TEST(RecordConfirmTest, AReceiptForAnotherChannelOrAnOldOneChangesNothing) {
  PublishedRecord pub(100);
  pub.Add("A", 1, Bytes(1));
  EXPECT_TRUE(pub.Confirm({"B", true, 0, 1, {}}).empty());
  EXPECT_FALSE(pub.heard_recorder());
  EXPECT_TRUE(pub.Confirm({"A", true, -5, 0, {}}).empty());
  EXPECT_FALSE(pub.AllConfirmed());
  EXPECT_TRUE(pub.Confirm({"A", true, 0, 1, {}}).empty());
  EXPECT_TRUE(pub.AllConfirmed());
  pub.Add("A", 1, Bytes(1));  // a seq already confirmed (a node that rejoins) is not kept
  EXPECT_TRUE(pub.AllConfirmed());
}

}  // namespace
}  // namespace dmpl
