// The confidence intervals against closed forms and the standard tables (Garwood's exact Poisson
// limits for 1 and 10 events; Wilson's interval evaluated by hand for 5/10 and 3/10^6).
#include <gtest/gtest.h>

#include <cmath>

#include "stats.hpp"

namespace test_stats {

using namespace tagbench;
using namespace tagbench::bench;

TEST(Wilson, MatchesKnownIntervals) {
  // 0 of 10: the upper bound is z^2 / (n + z^2).
  const auto a = wilson_interval(0, 10);
  EXPECT_EQ(a.lo, 0.0);
  EXPECT_NEAR(a.hi, kZ95 * kZ95 / (10 + kZ95 * kZ95), 1e-12);
  const auto b = wilson_interval(5, 10);
  EXPECT_NEAR(b.lo, 0.2365931, 1e-6);
  EXPECT_NEAR(b.hi, 0.7634069, 1e-6);
  const auto c = wilson_interval(10, 10);
  EXPECT_EQ(c.hi, 1.0);
  EXPECT_NEAR(c.lo, 1 - a.hi, 1e-12);  // symmetric to 0 of 10
  const auto d = wilson_interval(3, 1000000);
  EXPECT_LT(d.lo, 3e-6);
  EXPECT_GT(d.hi, 3e-6);
  EXPECT_NEAR(d.lo, 1.02027e-6, 1e-10);
  EXPECT_NEAR(d.hi, 8.82115e-6, 1e-10);
  const auto e = wilson_interval(0, 0);
  EXPECT_EQ(e.lo, 0.0);
  EXPECT_EQ(e.hi, 1.0);
}

TEST(Gamma, RegularizedPAgreesWithClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
    EXPECT_NEAR(regularized_gamma_p(1, x), 1 - std::exp(-x), 1e-13) << x;
    // a = 2: 1 - e^-x (1 + x); a = 3: 1 - e^-x (1 + x + x^2/2).
    EXPECT_NEAR(regularized_gamma_p(2, x), 1 - std::exp(-x) * (1 + x), 1e-13) << x;
    EXPECT_NEAR(regularized_gamma_p(3, x), 1 - std::exp(-x) * (1 + x + x * x / 2), 1e-13) << x;
  }
  EXPECT_EQ(regularized_gamma_p(4, 0), 0.0);
  // Large a: the median of gamma(a) is close to a - 1/3.
  EXPECT_NEAR(regularized_gamma_p(1e4, 1e4 - 1.0 / 3), 0.5, 1e-4);
  EXPECT_NEAR(gamma_quantile(1, 0.5), std::log(2.0), 1e-12);
}

TEST(Poisson, ExactIntervalsMatchGarwood) {
  const auto z = poisson_interval(0, 1);
  EXPECT_EQ(z.lo, 0.0);
  EXPECT_NEAR(z.hi, std::log(40.0), 1e-9);  // P(X = 0) = 0.025 at lambda = ln 40
  const auto one = poisson_interval(1, 1);
  EXPECT_NEAR(one.lo, -std::log(0.975), 1e-9);  // P(X >= 1) = 0.025
  EXPECT_NEAR(one.hi, 5.571643, 1e-5);
  const auto ten = poisson_interval(10, 1);
  EXPECT_NEAR(ten.lo, 4.795389, 1e-5);
  EXPECT_NEAR(ten.hi, 18.390356, 1e-5);
  // The exposure scales the rate.
  const auto scaled = poisson_interval(10, 4);
  EXPECT_NEAR(scaled.lo, ten.lo / 4, 1e-12);
  EXPECT_NEAR(scaled.hi, ten.hi / 4, 1e-12);
  // Large counts: close to the normal approximation count +- 1.96 sqrt(count).
  const auto big = poisson_interval(1000000, 1);
  EXPECT_NEAR(big.lo, 1e6 - kZ95 * 1000, 5);
  EXPECT_NEAR(big.hi, 1e6 + kZ95 * 1000, 5);
}

}  // namespace test_stats
