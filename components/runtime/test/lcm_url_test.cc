#include "components/runtime/lcm_url.h"

#include <gtest/gtest.h>

#include <cstring>

namespace dmpl {
namespace {

std::string Bus(const std::string& base, int bus) {
  std::string why;
  const std::optional<std::string> url = BusUrl(base, bus, &why);
  EXPECT_TRUE(url.has_value()) << why;
  return url.value_or("");
}

TEST(LcmUrlTest, EachBusOnItsOwnPortWithTheSameGroupAndOptions) {
  EXPECT_EQ(Bus("udpm://239.255.76.67:7667", 1), "udpm://239.255.76.67:8667");
  EXPECT_EQ(Bus("udpm://239.255.76.67:7700?ttl=0", 2), "udpm://239.255.76.67:9700?ttl=0");
  EXPECT_EQ(Bus("udpm://239.255.76.67:7700?ttl=1&recv_buf_size=4194304", 1),
            "udpm://239.255.76.67:8700?ttl=1&recv_buf_size=4194304");
}

TEST(LcmUrlTest, AUrlWithoutAPortHasLcmsDefault) {
  // Once appended after the options: "...?ttl=1:8667".
  EXPECT_EQ(Bus("udpm://239.255.76.67?ttl=1", 1), "udpm://239.255.76.67:8667?ttl=1");
  EXPECT_EQ(Bus("udpm://239.255.76.67", 2), "udpm://239.255.76.67:9667");
}

TEST(LcmUrlTest, TheManagementBusAndOtherProvidersKeepTheURL) {
  EXPECT_EQ(Bus("udpm://239.255.76.67?ttl=1", 0), "udpm://239.255.76.67?ttl=1");
  EXPECT_EQ(Bus("memq://", 3), "memq://");
  EXPECT_EQ(Bus("file:///tmp/x.lcmlog?mode=r", 1), "file:///tmp/x.lcmlog?mode=r");
}

TEST(LcmUrlTest, APortThatIsNotOneIsRefused) {
  for (const char* bad : {"udpm://239.255.76.67:x?ttl=0", "udpm://239.255.76.67:?ttl=0",
                          "udpm://239.255.76.67:65000", "udpm://239.255.76.67:123456"}) {
    std::string why;
    EXPECT_FALSE(BusUrl(bad, 1, &why).has_value()) << bad;
    EXPECT_NE(why.find(bad), std::string::npos) << why;
  }
}

TEST(LcmUrlTest, TheCFunctionPythonCallsSaysTheSame) {
  char out[128];
  ASSERT_EQ(dmpl_bus_url("udpm://239.255.76.67?ttl=1", 1, out, sizeof out), 0);
  EXPECT_STREQ(out, "udpm://239.255.76.67:8667?ttl=1");
  EXPECT_EQ(dmpl_bus_url("udpm://239.255.76.67:x", 1, out, sizeof out), -1);
  EXPECT_NE(std::strstr(out, "port"), nullptr);
  EXPECT_EQ(dmpl_bus_url("udpm://239.255.76.67:7667", 1, out, 8), -2);
}

}  // namespace
}  // namespace dmpl
