#pragma once
// Reading an encoded message without decoding it (recorders look at every message of a run).
// Every message begins with its type's 8-byte hash; the types of the loop then carry the run
// they belong to (run_id), and every dmpl type then its utime and seq, all big-endian int64.
#include <cstddef>
#include <cstdint>

namespace dmpl {

// True when the message's type carries run_id first.
bool CarriesRunId(const void* data, size_t size);
// The message's run_id, or 0 when its type carries none.
int64_t RunIdOf(const void* data, size_t size);
// The message's seq, or -1 when it is too short to hold one.
int64_t SeqOf(const void* data, size_t size);
// Where the fields after utime and seq begin.
size_t HeaderSize(const void* data, size_t size);

}  // namespace dmpl
