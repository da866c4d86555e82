#include "components/runtime/check.h"

#include <cstdio>
#include <cstdlib>

namespace dmpl::internal {

void AbortWithMessage(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "dmpl: internal invariant failed: %s at %s:%d\n", condition, file, line);
  std::fflush(stderr);
  std::abort();
}

void ThrowWithMessage(const char* condition, const std::string& message) {
  (void)condition;
  throw std::invalid_argument(message);
}

}  // namespace dmpl::internal
