#pragma once
// A recorder that misses nothing on a lossy network (README, "Lockstep and real time"). The
// loop's own resending (resend.h) only covers what a node of the loop waits for: a status that
// only the recorder reads, or a run's last messages, once lost stay lost, and the run's metrics
// would differ from those of the same run without loss. So each publisher keeps what it sent on
// its recorded channels until the recorder confirms it:
//   publisher -> recorder: a ledger per channel, "(after, through]: n messages";
//   recorder -> publisher: a receipt, "complete through" or "of (after, through] I have these
//                          seqs", and the publisher sends the others again (the same bytes).
// A stopping publisher waits (a bounded time) for the receipts of its last messages.
// Both sides are pure (no LCM): the nodes and the recorder move their messages.
#include <cstdint>
#include <deque>
#include <string>
#include <unordered_map>
#include <vector>

namespace dmpl {

// One channel's line of a ledger.
struct LedgerEntry {
  std::string channel;
  int64_t after_seq = -1;
  int64_t through_seq = -1;
  int32_t count = 0;
};

// The recorder's answer to one ledger entry.
struct Receipt {
  std::string channel;
  bool complete = false;
  int64_t after_seq = -1;
  int64_t through_seq = -1;
  std::vector<int64_t> have;  // incomplete: the seqs it has, once per message
};

// The publisher's side: what it sent and the recorder has not yet confirmed.
class PublishedRecord {
 public:
  // depth: at most this many unconfirmed messages are kept per channel (the oldest go first:
  // without a recorder nothing is ever confirmed).
  explicit PublishedRecord(size_t depth) : depth_(depth) {}

  // A message published on `channel` for tick `seq` (its encoded bytes).
  void Add(const std::string& channel, int64_t seq, std::vector<uint8_t> bytes);
  // One entry per channel with something published: what the recorder should have.
  std::vector<LedgerEntry> Ledger() const;
  // Takes a receipt; returns the messages to send again (pointers into the kept bytes, valid
  // until the next Add or Confirm).
  std::vector<const std::vector<uint8_t>*> Confirm(const Receipt& receipt);
  // Every message published so far is confirmed.
  bool AllConfirmed() const;
  // A receipt has ever arrived: a recorder that confirms is listening.
  bool heard_recorder() const { return heard_recorder_; }
  int64_t sent_again() const { return sent_again_; }
  int64_t dropped_unconfirmed() const { return dropped_unconfirmed_; }

 private:
  struct Kept {
    int64_t seq;
    std::vector<uint8_t> bytes;
  };
  struct Channel {
    int64_t confirmed_through = -1;  // the recorder has every message up to this seq
    int64_t last_seq = -1;
    std::deque<Kept> unconfirmed;    // seqs > confirmed_through, in publication order
  };
  size_t depth_;
  std::unordered_map<std::string, Channel> channels_;
  std::vector<std::string> order_;  // channels in the order first published (stable ledgers)
  bool heard_recorder_ = false;
  int64_t sent_again_ = 0;
  int64_t dropped_unconfirmed_ = 0;
};

// The recorder's side: which messages of each seq it recorded (by a hash of their bytes), over a
// window of the latest seqs per channel. It also tells a copy from a new message: a message
// sent again, by the loop's resending or at the recorder's request, is recorded once.
class ReceivedRecord {
 public:
  // window: how many seqs back a channel's record goes (a ledger older than that is taken as
  // complete: it cannot be checked).
  explicit ReceivedRecord(int64_t window = 1 << 16) : window_(window) {}

  enum class Verdict { kNew, kCopy, kUnknown };
  // A message of the run on `channel` with `seq` and the hash of its bytes: new (now counted),
  // a copy of one recorded, or unknown (no seq, or outside the window: not counted).
  Verdict Add(const std::string& channel, int64_t seq, uint64_t hash);
  // The answer to one ledger entry.
  Receipt Answer(const LedgerEntry& entry) const;
  // The newest seq recorded on `channel` (-1: none).
  int64_t newest(const std::string& channel) const;

 private:
  struct Slot {
    uint64_t first_hash = 0;
    uint16_t count = 0;
  };
  struct Channel {
    int64_t base = 0;          // the seq of slots[0]
    std::deque<Slot> slots;    // per seq: its first message's hash, how many messages
    std::unordered_map<int64_t, std::vector<uint64_t>> more;  // hashes after the first
    bool slid = false;         // seqs before base were forgotten
    int64_t newest = -1;
  };
  int Count(const Channel& c, int64_t seq) const;
  int64_t window_;
  std::unordered_map<std::string, Channel> channels_;
};

// A 64-bit hash of a message's bytes (how the recorder tells copies apart; never stored).
uint64_t HashBytes(const void* data, size_t size);

}  // namespace dmpl
