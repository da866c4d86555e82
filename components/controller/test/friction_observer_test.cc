#include "components/controller/friction_observer.h"

#include "components/controller/controller_params.h"
#include "components/controller/rolling_median.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace dmpl {
namespace {

// An explorer's slide as the joints feel it: pushes of 0.05-0.5 N (the 0.1 N asked, chattering),
// the friction at `mu` times the push while it slips, less while it sticks (`stick` of the
// ticks), and a tenth of the ticks wild (a contact's chatter, tangential forces up to 3 N).
void Slide(FrictionObserver* o, double mu, int ticks, std::mt19937* rng, double stick = 0.3) {
  std::uniform_real_distribution<double> push(0.05, 0.5), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (int k = 0; k < ticks; ++k) {
    const double n = push(*rng);
    double t = mu * n * (1.0 + noise(*rng));
    if (unit(*rng) < stick) t *= unit(*rng);
    if (unit(*rng) < 0.1) t = 3.0 * unit(*rng);
    o->AddSlide(n, t);
  }
}

TEST(RollingMedianTest, TheOldestValueGivesWayToTheNewest) {
  RollingMedian m(3);
  EXPECT_EQ(m.Median(), 0.0);
  m.Add(5.0);
  m.Add(1.0);
  EXPECT_EQ(m.Median(), 5.0);  // the upper of two
  m.Add(3.0);
  EXPECT_EQ(m.Median(), 3.0);
  m.Add(9.0);  // 5 goes: 1, 3, 9
  m.Add(8.0);  // 1 goes: 3, 9, 8
  EXPECT_EQ(m.size(), 3);
  EXPECT_EQ(m.Median(), 8.0);
}

TEST(FrictionObserverTest, NothingIsObservedBeforeEnoughSlides) {
  FrictionObserverParams p;
  FrictionObserver o(p);
  std::mt19937 rng(1);
  Slide(&o, 0.6, p.min_samples - 1, &rng);
  EXPECT_EQ(o.friction(), 0.0);
  Slide(&o, 0.6, p.update_every, &rng);
  EXPECT_GT(o.friction(), 0.0);
}

TEST(FrictionObserverTest, TheMedianTellsSlickFromGrippyDespiteStickingAndChatter) {
  // With 30 % of the ticks sticking and 10 % wild, the median lies a little below the friction:
  // a plan that relies on it relies on less than the object gives, never more than 10 % more.
  for (const double mu : {0.3, 0.6, 1.0, 1.5}) {
    FrictionObserver o(FrictionObserverParams{});
    std::mt19937 rng(7);
    Slide(&o, mu, 3000, &rng);
    EXPECT_GT(o.friction(), 0.7 * mu) << mu;
    EXPECT_LT(o.friction(), 1.1 * mu) << mu;
  }
}

TEST(FrictionObserverTest, PushesBelowTheSensorsNoiseAndBadNumbersAreIgnored) {
  FrictionObserverParams p;
  p.min_samples = 10;
  p.update_every = 1;
  FrictionObserver o(p);
  for (int k = 0; k < 100; ++k) o.AddSlide(0.2, 0.1);  // 0.5
  // A 0.01 N reading under a 0.1 N drag would say 10; NaN and infinities say nothing.
  for (int k = 0; k < 1000; ++k) {
    o.AddSlide(0.01, 0.1);
    o.AddSlide(std::numeric_limits<double>::quiet_NaN(), 0.1);
    o.AddSlide(0.2, std::numeric_limits<double>::infinity());
    o.AddSlide(-1.0, 0.1);
  }
  EXPECT_EQ(o.samples(), 100);
  EXPECT_DOUBLE_EQ(o.friction(), 0.5);
}

TEST(FrictionObserverTest, ItFollowsTheLastWindowOfSlides) {
  FrictionObserverParams p;
  FrictionObserver o(p);
  std::mt19937 rng(3);
  Slide(&o, 1.0, 5000, &rng);
  const double grippy = o.friction();
  Slide(&o, 0.4, p.window, &rng);  // the object's surface changed under the fingers
  EXPECT_LT(o.friction(), 0.5 * grippy);
  EXPECT_EQ(o.samples(), p.window);
}

TEST(FrictionObserverTest, MoreSamplesAskedThanKeptIsAConfigErrorNamingTheKey) {
  ControllerParams p;
  p.friction_observer.min_samples = p.friction_observer.window + 1;
  try {
    p.Validate("exp.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("exp.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("key 'controller.friction_observer.min_samples'"), std::string::npos)
        << what;
  }
  p = ControllerParams{};
  p.weight_observer.min_samples = p.weight_observer.window + 1;
  EXPECT_THROW(p.Validate("exp.yaml"), ConfigError);
  EXPECT_NO_THROW(ControllerParams{}.Validate("exp.yaml"));
}

}  // namespace
}  // namespace dmpl
