#pragma once
// A node's journal: the inputs that made its state, appended as they come, so that a restarted
// node replays them and takes up exactly where it was (the supervisor's charts; README,
// "Faults"). Each entry is written with one write(2): a process killed at any moment leaves
// every entry it completed in the file, at most the last one cut short.
// Format: per entry a tag byte, the length (uint32, little-endian) and that many bytes.
#include <cstdint>
#include <string>
#include <vector>

namespace dmpl {

struct JournalEntry {
  uint8_t tag = 0;
  std::vector<uint8_t> bytes;
};

// The entries of the journal at `path` (none when there is no file). An entry cut short at the
// end (a kill mid-write) is left out and counted in *cut_short. Throws std::runtime_error when
// the file exists but cannot be read.
std::vector<JournalEntry> ReadJournal(const std::string& path, int* cut_short);

class JournalWriter {
 public:
  // Opens `path` to append (creating it). Throws std::runtime_error naming the file.
  explicit JournalWriter(const std::string& path);
  ~JournalWriter();
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;

  // Appends one entry. Returns false (errno set) when the write failed.
  bool Append(uint8_t tag, const void* data, size_t size);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::vector<uint8_t> buffer_;
};

}  // namespace dmpl
