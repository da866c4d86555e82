#include "components/runtime/lcm_url.h"

#include <cstring>

namespace dmpl {

namespace {

constexpr char kUdpm[] = "udpm://";
constexpr int kLcmDefaultPort = 7667;
constexpr int kPortsPerBus = 1000;

}  // namespace

std::optional<std::string> BusUrl(const std::string& base_url, int bus, std::string* why) {
  if (bus == 0 || base_url.rfind(kUdpm, 0) != 0) return base_url;
  const size_t host = std::strlen(kUdpm);
  const size_t options = std::min(base_url.find('?', host), base_url.size());
  const size_t colon = base_url.find(':', host);
  const std::string group = base_url.substr(0, std::min(colon, options));
  int port = kLcmDefaultPort;
  if (colon < options) {
    const std::string digits = base_url.substr(colon + 1, options - colon - 1);
    const bool number = !digits.empty() && digits.size() <= 5 &&
                        digits.find_first_not_of("0123456789") == std::string::npos;
    port = number ? std::stoi(digits) : -1;
  }
  if (port < 0 || port + kPortsPerBus * bus > 65535) {
    *why = "LCM URL '" + base_url + "': its port must be a number of at most " +
           std::to_string(65535 - kPortsPerBus * bus) + " (bus " + std::to_string(bus) +
           " listens " + std::to_string(kPortsPerBus * bus) + " ports above it)";
    return std::nullopt;
  }
  return group + ":" + std::to_string(port + kPortsPerBus * bus) + base_url.substr(options);
}

}  // namespace dmpl

extern "C" int dmpl_bus_url(const char* base_url, int bus, char* out, int size) {
  std::string why;
  const std::optional<std::string> url = dmpl::BusUrl(base_url, bus, &why);
  const std::string& text = url ? *url : why;
  if (size <= 0 || text.size() + 1 > static_cast<size_t>(size)) return -2;
  std::memcpy(out, text.c_str(), text.size() + 1);
  return url ? 0 : -1;
}
