#pragma once
// The one rule for the URLs of a run's buses (channels.h puts each group of channels on its own
// bus): with udpm://GROUP[:PORT][?OPTIONS], bus b listens on PORT + 1000 * b (PORT is LCM's 7667
// when the URL gives none) with the same group and options; any other provider (memq://,
// file://) is one bus. C++ uses it directly; Python through the C function below (ctypes, from
// the build's python/ directory) and lcm-spy through Python, so all of them agree.
#include <optional>
#include <string>

namespace dmpl {

// The URL of bus `bus` (>= 0) of a run on `base_url`; nullopt, with `why`, for a udpm URL whose
// port is not a number or does not leave room for the bus's.
std::optional<std::string> BusUrl(const std::string& base_url, int bus, std::string* why);

}  // namespace dmpl

// For Python (ctypes): writes the URL (or, on failure, why) into `out` of `size` bytes, NUL
// terminated. Returns 0, or -1 for a bad URL, or -2 when `out` is too small.
extern "C" int dmpl_bus_url(const char* base_url, int bus, char* out, int size);
