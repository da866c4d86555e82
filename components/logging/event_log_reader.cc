#include "components/logging/event_log_reader.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dmpl {
namespace {

constexpr uint8_t kSync[4] = {0xED, 0xA1, 0xDA, 0x01};
constexpr size_t kHeader = 28;
constexpr uint32_t kMaxChannel = 256;  // LCM's limit on channel names

uint64_t BigEndian(const uint8_t* p, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

EventLogReader::EventLogReader(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY);
  if (fd < 0) throw std::runtime_error("cannot read log '" + path + "': " + std::strerror(errno));
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(fd);
    throw std::runtime_error("cannot read log '" + path + "': not a regular file");
  }
  size_ = static_cast<size_t>(st.st_size);
  if (size_ > 0) {
    void* p = mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      close(fd);
      throw std::runtime_error("cannot map log '" + path + "': " + std::strerror(errno));
    }
    madvise(p, size_, MADV_SEQUENTIAL);
    base_ = static_cast<const uint8_t*>(p);
  }
  close(fd);
}

EventLogReader::~EventLogReader() {
  if (base_ != nullptr) munmap(const_cast<uint8_t*>(base_), size_);
}

// A complete, plausible event at `pos`: the sync word, a printable channel name of a sane length,
// and a payload inside the file.
bool EventLogReader::EventAt(size_t pos, LogEvent* event, size_t* end) const {
  if (size_ - pos < kHeader || std::memcmp(base_ + pos, kSync, 4) != 0) return false;
  const uint8_t* h = base_ + pos;
  const uint32_t channel_len = static_cast<uint32_t>(BigEndian(h + 20, 4));
  const uint32_t data_len = static_cast<uint32_t>(BigEndian(h + 24, 4));
  if (channel_len == 0 || channel_len > kMaxChannel) return false;
  if (size_ - pos - kHeader < static_cast<uint64_t>(channel_len) + data_len) return false;
  const char* name = reinterpret_cast<const char*>(h + kHeader);
  for (uint32_t i = 0; i < channel_len; ++i) {
    if (name[i] < 0x20 || name[i] > 0x7e) return false;
  }
  event->eventnum = static_cast<int64_t>(BigEndian(h + 4, 8));
  event->timestamp = static_cast<int64_t>(BigEndian(h + 12, 8));
  event->channel = std::string_view(name, channel_len);
  event->data = h + kHeader + channel_len;
  event->size = data_len;
  *end = pos + kHeader + channel_len + data_len;
  return true;
}

bool EventLogReader::Next(LogEvent* event) {
  // The previous event's view is no longer needed: give the pages before it back, 64 MB at a
  // time, so that reading a long log needs little memory.
  constexpr size_t kRelease = 64 << 20;
  if (pos_ - released_ > 2 * kRelease) {
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    const size_t upto = (pos_ - kRelease) / page * page;
    madvise(const_cast<uint8_t*>(base_) + released_, upto - released_, MADV_DONTNEED);
    released_ = upto;
  }
  size_t end = 0;
  if (pos_ < size_ && EventAt(pos_, event, &end)) {
    pos_ = end;
    return true;
  }
  // Not an event here: look for the next one. If none follows, what is left is a torn last
  // event (the sync word is there) or garbage.
  for (size_t p = pos_ + 1; p + kHeader <= size_; ++p) {
    const void* hit = std::memchr(base_ + p, kSync[0], size_ - p);
    if (hit == nullptr) break;
    p = static_cast<const uint8_t*>(hit) - base_;
    if (EventAt(p, event, &end)) {
      skipped_bytes_ += static_cast<int64_t>(p - pos_);
      ++resyncs_;
      pos_ = end;
      return true;
    }
  }
  if (pos_ < size_) {
    truncated_ = size_ - pos_ >= 4 && std::memcmp(base_ + pos_, kSync, 4) == 0;
    if (!truncated_) {
      skipped_bytes_ += static_cast<int64_t>(size_ - pos_);
      ++resyncs_;
    }
    pos_ = size_;
  }
  return false;
}

}  // namespace dmpl
