#pragma once
// 95 % confidence intervals for the experiments' rates: a proportion (accepted quads out of
// candidate quads, images with a false detection out of images, frames detected) gets Wilson's
// score interval; a count of events over an exposure (false detections per image or per megapixel, where
// an image can hold several) gets the exact Poisson (Garwood) interval.
#include <cstdint>

namespace tagbench::bench {

struct Interval {
  double lo = 0, hi = 0;
};

inline constexpr double kZ95 = 1.959963984540054;  // the standard normal's 97.5 % quantile

// Wilson score interval of k successes in n trials (n > 0); [0, 1] for n == 0.
Interval wilson_interval(std::uint64_t k, std::uint64_t n, double z = kZ95);

// Exact two-sided 95 % interval of a Poisson rate: `count` events over `exposure` (> 0) units.
// lo = chi2_{0.025}(2 count) / 2 / exposure (0 when count == 0), hi = chi2_{0.975}(2 count + 2) / 2 / exposure.
Interval poisson_interval(std::uint64_t count, double exposure);

// The regularized lower incomplete gamma function P(a, x), a > 0, x >= 0.
double regularized_gamma_p(double a, double x);

// x such that P(a, x) = p, for 0 < p < 1 (the gamma(a, 1) distribution's quantile).
double gamma_quantile(double a, double p);

}  // namespace tagbench::bench
