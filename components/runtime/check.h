#pragma once
// Two kinds of failure, in the spirit of Drake's DRAKE_DEMAND / DRAKE_THROW_UNLESS:
//  - DMPL_DEMAND(cond): an internal invariant. If it is false the program is wrong: abort loudly.
//  - DMPL_THROW_UNLESS(cond, msg): bad input from a caller or a file: throw with a clear message.
#include <sstream>
#include <stdexcept>
#include <string>

namespace dmpl::internal {
[[noreturn]] void AbortWithMessage(const char* condition, const char* file, int line);
[[noreturn]] void ThrowWithMessage(const char* condition, const std::string& message);
}  // namespace dmpl::internal

#define DMPL_DEMAND(condition)                                                  \
  do {                                                                          \
    if (!(condition)) {                                                         \
      ::dmpl::internal::AbortWithMessage(#condition, __FILE__, __LINE__);       \
    }                                                                           \
  } while (0)

// `stream_expr` is streamed into the message: DMPL_THROW_UNLESS(m > 0, "mass " << m << " <= 0").
#define DMPL_THROW_UNLESS(condition, stream_expr)                               \
  do {                                                                          \
    if (!(condition)) {                                                         \
      std::ostringstream dmpl_throw_os;                                         \
      dmpl_throw_os << stream_expr;                                             \
      ::dmpl::internal::ThrowWithMessage(#condition, dmpl_throw_os.str());      \
    }                                                                           \
  } while (0)
