#include "components/runtime/journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace dmpl {

namespace {
constexpr size_t kHeaderSize = 5;  // tag + uint32 length
}  // namespace

std::vector<JournalEntry> ReadJournal(const std::string& path, int* cut_short) {
  *cut_short = 0;
  std::vector<JournalEntry> entries;
  if (access(path.c_str(), F_OK) != 0) return entries;  // none yet: a first start
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error("cannot read the journal '" + path + "': " + std::strerror(errno));
  }
  const std::vector<uint8_t> data((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  size_t at = 0;
  while (at < data.size()) {
    if (data.size() - at < kHeaderSize) break;
    uint32_t size = 0;
    for (int i = 0; i < 4; ++i) size |= static_cast<uint32_t>(data[at + 1 + i]) << (8 * i);
    if (data.size() - at - kHeaderSize < size) break;
    entries.push_back({data[at], {data.begin() + static_cast<std::ptrdiff_t>(at + kHeaderSize),
                                  data.begin() + static_cast<std::ptrdiff_t>(at + kHeaderSize + size)}});
    at += kHeaderSize + size;
  }
  if (at < data.size()) *cut_short = 1;
  return entries;
}

JournalWriter::JournalWriter(const std::string& path) : path_(path) {
  fd_ = open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw std::runtime_error("cannot open the journal '" + path + "': " + std::strerror(errno));
  }
}

JournalWriter::~JournalWriter() {
  if (fd_ >= 0) close(fd_);
}

bool JournalWriter::Append(uint8_t tag, const void* data, size_t size) {
  buffer_.resize(kHeaderSize + size);
  buffer_[0] = tag;
  const auto n = static_cast<uint32_t>(size);
  for (int i = 0; i < 4; ++i) buffer_[1 + i] = static_cast<uint8_t>(n >> (8 * i));
  if (size > 0) std::memcpy(buffer_.data() + kHeaderSize, data, size);
  size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t w = write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    done += static_cast<size_t>(w);
  }
  return true;
}

}  // namespace dmpl
