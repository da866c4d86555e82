#include "components/runtime/record_confirm.h"

#include <algorithm>
#include <cstring>

namespace dmpl {

void PublishedRecord::Add(const std::string& channel, int64_t seq, std::vector<uint8_t> bytes) {
  auto [it, first] = channels_.try_emplace(channel);
  Channel& ch = it->second;
  if (first) {
    order_.push_back(channel);
    ch.confirmed_through = seq - 1;
  }
  if (seq <= ch.confirmed_through) return;  // a seq the recorder confirmed (a node rejoining)
  // The same bytes again (a status published twice unchanged) are one message to the recorder.
  for (auto k = ch.unconfirmed.rbegin(); k != ch.unconfirmed.rend() && k->seq == seq; ++k) {
    if (k->bytes == bytes) return;
  }
  ch.last_seq = std::max(ch.last_seq, seq);
  ch.unconfirmed.push_back({seq, std::move(bytes)});
  if (ch.unconfirmed.size() <= depth_) return;
  // Too many unconfirmed (no recorder, or it fell behind): give up the oldest seq whole, so
  // that the ledger accounts for exactly what can still be sent again.
  const int64_t oldest = ch.unconfirmed.front().seq;
  while (!ch.unconfirmed.empty() && ch.unconfirmed.front().seq == oldest) {
    ch.unconfirmed.pop_front();
    ++dropped_unconfirmed_;
  }
  ch.confirmed_through = oldest;
}

std::vector<LedgerEntry> PublishedRecord::Ledger() const {
  std::vector<LedgerEntry> out;
  for (const std::string& name : order_) {
    const Channel& ch = channels_.at(name);
    if (ch.unconfirmed.empty()) continue;
    out.push_back({name, ch.confirmed_through, ch.last_seq,
                   static_cast<int32_t>(ch.unconfirmed.size())});
  }
  return out;
}

std::vector<const std::vector<uint8_t>*> PublishedRecord::Confirm(const Receipt& receipt) {
  std::vector<const std::vector<uint8_t>*> again;
  auto it = channels_.find(receipt.channel);
  if (it == channels_.end()) return again;
  heard_recorder_ = true;
  Channel& ch = it->second;
  if (receipt.complete) {
    if (receipt.through_seq <= ch.confirmed_through) return again;
    ch.confirmed_through = receipt.through_seq;
    while (!ch.unconfirmed.empty() && ch.unconfirmed.front().seq <= ch.confirmed_through) {
      ch.unconfirmed.pop_front();
    }
    return again;
  }
  // Of each seq the recorder has its first `have` messages (they are published in order and
  // each is recorded once): the later ones of that seq are sent again.
  std::unordered_map<int64_t, int> have;
  for (int64_t seq : receipt.have) ++have[seq];
  for (const Kept& k : ch.unconfirmed) {
    if (k.seq <= receipt.after_seq || k.seq > receipt.through_seq) continue;
    int& recorded = have[k.seq];
    if (recorded > 0) {
      --recorded;
    } else {
      again.push_back(&k.bytes);
    }
  }
  sent_again_ += static_cast<int64_t>(again.size());
  return again;
}

bool PublishedRecord::AllConfirmed() const {
  return std::all_of(channels_.begin(), channels_.end(),
                     [](const auto& kv) { return kv.second.unconfirmed.empty(); });
}

uint64_t HashBytes(const void* data, size_t size) {
  // FNV-1a's step over eight bytes at a time (every message the recorder hears is hashed, a few
  // kB a tick: byte by byte it was 5 % of the one-process loop), then the tail, then a final
  // mix so that the last word's bits reach the low ones too.
  const auto* bytes = static_cast<const uint8_t*>(data);
  constexpr uint64_t kPrime = 1099511628211ull;
  uint64_t hash = 14695981039346656037ull ^ size;
  size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    hash = (hash ^ word) * kPrime;
    hash ^= hash >> 29;
  }
  for (; i < size; ++i) hash = (hash ^ bytes[i]) * kPrime;
  hash ^= hash >> 32;
  hash *= 0x9e3779b97f4a7c15ull;
  return hash ^ (hash >> 29);
}

ReceivedRecord::Verdict ReceivedRecord::Add(const std::string& channel, int64_t seq,
                                            uint64_t hash) {
  if (seq < 0) return Verdict::kUnknown;
  Channel& c = channels_[channel];
  if (c.slots.empty()) c.base = seq;
  const int64_t end = c.base + static_cast<int64_t>(c.slots.size());
  if (seq < c.base) {
    // A first message that arrives late (sent again): the window grows back, unless it moved on.
    if (c.slid || c.base - seq + static_cast<int64_t>(c.slots.size()) > window_) {
      return Verdict::kUnknown;
    }
    c.slots.insert(c.slots.begin(), static_cast<size_t>(c.base - seq), Slot{});
    c.base = seq;
  }
  if (seq >= end + window_) return Verdict::kUnknown;  // absurdly far ahead (a forged seq)
  if (seq >= end) c.slots.resize(static_cast<size_t>(seq - c.base + 1));
  Slot& slot = c.slots[static_cast<size_t>(seq - c.base)];
  if (slot.count == 0) {
    slot.first_hash = hash;
  } else {
    if (slot.first_hash == hash) return Verdict::kCopy;
    std::vector<uint64_t>& more = c.more[seq];
    if (std::find(more.begin(), more.end(), hash) != more.end()) return Verdict::kCopy;
    more.push_back(hash);
  }
  if (slot.count < UINT16_MAX) ++slot.count;
  c.newest = std::max(c.newest, seq);
  while (static_cast<int64_t>(c.slots.size()) > window_) {
    if (c.slots.front().count > 1) c.more.erase(c.base);
    c.slots.pop_front();
    ++c.base;
    c.slid = true;
  }
  return Verdict::kNew;
}

int64_t ReceivedRecord::newest(const std::string& channel) const {
  auto it = channels_.find(channel);
  return it == channels_.end() ? -1 : it->second.newest;
}

int ReceivedRecord::Count(const Channel& c, int64_t seq) const {
  const int64_t i = seq - c.base;
  return i < 0 || i >= static_cast<int64_t>(c.slots.size()) ? 0 : c.slots[static_cast<size_t>(i)].count;
}

Receipt ReceivedRecord::Answer(const LedgerEntry& entry) const {
  Receipt r{entry.channel, true, entry.after_seq, entry.through_seq, {}};
  auto it = channels_.find(entry.channel);
  const int64_t from = entry.after_seq + 1;
  if (entry.count <= 0 || entry.through_seq < from) return r;
  if (it != channels_.end() && it->second.slid && from < it->second.base) return r;  // too old
  int64_t recorded = 0;
  if (it != channels_.end()) {
    for (int64_t seq = from; seq <= entry.through_seq; ++seq) {
      for (int n = Count(it->second, seq); n > 0; --n) r.have.push_back(seq);
    }
    recorded = static_cast<int64_t>(r.have.size());
  }
  if (recorded >= entry.count) {
    r.have.clear();
    return r;
  }
  r.complete = false;
  return r;
}

}  // namespace dmpl
