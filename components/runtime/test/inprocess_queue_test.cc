#include "components/runtime/inprocess_queue.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dmpl/heartbeat_t.hpp"

namespace dmpl {
namespace {

// What a subscription saw: "<subscriber>:<channel>:<payload>".
struct Seen {
  std::vector<std::string> events;
  InProcessQueue::Handler Record(const std::string& who) {
    return [this, who](const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      events.push_back(who + ":" + channel + ":" +
                       std::string(static_cast<const char*>(rbuf->data), rbuf->data_size));
    };
  }
};

void Put(InProcessQueue& q, const std::string& channel, const std::string& text) {
  q.Publish(channel, text.data(), text.size());
}

TEST(InProcessQueueTest, DeliversOneMessageAtATimeInPublishOrderToSubscribersInOrder) {
  InProcessQueue q;
  Seen seen;
  q.Subscribe("A", seen.Record("first"));
  q.Subscribe(".*", seen.Record("all"));
  Put(q, "A", "1");
  Put(q, "B", "2");
  EXPECT_EQ(q.pending(), 2u);
  EXPECT_TRUE(q.DeliverOne());
  EXPECT_EQ(seen.events, (std::vector<std::string>{"first:A:1", "all:A:1"}));
  EXPECT_TRUE(q.DeliverOne());
  EXPECT_EQ(seen.events.back(), "all:B:2");
  EXPECT_FALSE(q.DeliverOne());
}

TEST(InProcessQueueTest, APatternMatchesTheWholeChannelNameAsLcmDoes) {
  InProcessQueue q;
  Seen seen;
  q.Subscribe("DMPL_SENSORS", seen.Record("exact"));
  q.Subscribe("DMPL_.*_TRUE", seen.Record("truth"));
  Put(q, "DMPL_SENSORS_TRUE", "x");  // a prefix match is not a match
  Put(q, "DMPL_SENSORS", "y");
  while (q.DeliverOne()) {
  }
  EXPECT_EQ(seen.events, (std::vector<std::string>{"truth:DMPL_SENSORS_TRUE:x",
                                                   "exact:DMPL_SENSORS:y"}));
}

TEST(InProcessQueueTest, AnUnsubscribedHandlerHearsNothingMore) {
  InProcessQueue q;
  Seen seen;
  int a = q.Subscribe("C", seen.Record("a"));
  q.Subscribe("C", seen.Record("b"));
  Put(q, "C", "1");
  q.DeliverOne();
  q.Unsubscribe(a);
  Put(q, "C", "2");
  q.DeliverOne();
  EXPECT_EQ(seen.events, (std::vector<std::string>{"a:C:1", "b:C:1", "b:C:2"}));
}

TEST(InProcessQueueTest, APublishFromAHandlerIsDeliveredAfterTheCurrentMessage) {
  InProcessQueue q;
  std::vector<std::string> order;
  q.Subscribe("PING", [&](const lcm::ReceiveBuffer*, const std::string&) {
    order.push_back("ping");
    Put(q, "PONG", "");
  });
  q.Subscribe("PING", [&](const lcm::ReceiveBuffer*, const std::string&) {
    order.push_back("ping2");
  });
  q.Subscribe("PONG", [&](const lcm::ReceiveBuffer* rbuf, const std::string&) {
    order.push_back("pong" + std::to_string(rbuf->data_size));
  });
  Put(q, "PING", "");
  q.DeliverOne();
  EXPECT_EQ(order, (std::vector<std::string>{"ping", "ping2"}));
  q.DeliverOne();
  EXPECT_EQ(order.back(), "pong0");
}

TEST(InProcessQueueTest, ALcmMessageArrivesAsItWasEncodedAndBuffersAreReused) {
  InProcessQueue q;
  std::vector<heartbeat_t> got;
  q.Subscribe("HB", [&](const lcm::ReceiveBuffer* rbuf, const std::string&) {
    heartbeat_t m;
    ASSERT_GE(m.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)), 0);
    got.push_back(m);
  });
  for (int i = 0; i < 3; ++i) {
    heartbeat_t m{};
    m.utime = 1000 + i;
    m.process = std::string(static_cast<size_t>(3 - i), 'n');  // shrinking: a reused buffer resizes
    q.Publish("HB", m);
    q.DeliverOne();
  }
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[2].utime, 1002);
  EXPECT_EQ(got[2].process, "n");
}

TEST(InProcessQueueDeathTest, DeliveringFromInsideAHandlerFailsLoudly) {
  InProcessQueue q;
  q.Subscribe("X", [&](const lcm::ReceiveBuffer*, const std::string&) { q.DeliverOne(); });
  Put(q, "X", "");
  EXPECT_DEATH(q.DeliverOne(), "delivering");
}

}  // namespace
}  // namespace dmpl
