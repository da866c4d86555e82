#include <gtest/gtest.h>

#include <cmath>

#include "components/runtime/random.h"

namespace dmpl {
namespace {

TEST(RngTest, SameKeySameStreamDifferentKeyDifferentStream) {
  Rng a(1, 10, 2), b(1, 10, 2), c(1, 11, 2), d(2, 10, 2);
  const double x = a.Normal();
  EXPECT_EQ(x, b.Normal());
  EXPECT_NE(x, c.Normal());
  EXPECT_NE(x, d.Normal());
}

TEST(RngTest, NormalHasUnitVarianceAndZeroMean) {
  constexpr int kN = 100000;
  double sum = 0, sum2 = 0;
  Rng rng(7, 0, 0);
  for (int i = 0; i < kN; ++i) {
    const double x = rng.Normal();
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / kN;
  const double var = sum2 / kN - mean * mean;
  // Standard errors: 1/sqrt(N) for the mean, sqrt(2/N) for the variance; allow 4 of them.
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(kN));
  EXPECT_NEAR(var, 1.0, 4.0 * std::sqrt(2.0 / kN));
}

}  // namespace
}  // namespace dmpl
