#pragma once
// Decoding a message from outside. LCM's generated decode trusts the sizes a message carries: a
// negative or huge array length makes it throw (std::length_error, std::bad_alloc) rather than
// fail. Every node decodes through here, so that bad bytes are one counted failure, never a crash.
#include <cstdint>
#include <exception>

namespace dmpl {

// True when `data` (size bytes) is exactly one Msg, decoded into *msg.
template <typename Msg>
bool DecodeMessage(const void* data, uint32_t size, Msg* msg) {
  try {
    return msg->decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace dmpl
