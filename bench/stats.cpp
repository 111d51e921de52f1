#include "stats.hpp"

#include <cmath>
#include <limits>

namespace tagbench::bench {

Interval wilson_interval(std::uint64_t k, std::uint64_t n, double z) {
  if (n == 0) return {0, 1};
  const double nn = static_cast<double>(n), p = static_cast<double>(k) / nn, z2 = z * z;
  const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
  const double half = z / (1 + z2 / nn) * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn));
  // At k == 0 (k == n) the exact bound is 0 (1); rounding could leave 1e-17 on the wrong side.
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

double regularized_gamma_p(double a, double x) {
  if (x <= 0) return 0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    // Series: P = e^-x x^a / Gamma(a) * sum x^n / (a (a+1) ... (a+n)); converges fast for x < a + 1.
    double term = 1 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (term < sum * 1e-16) break;
    }
    return std::min(1.0, sum * std::exp(log_prefix));
  }
  // Continued fraction for Q = 1 - P (modified Lentz), which converges fast for x >= a + 1.
  const double tiny = std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon();
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1) < 1e-16) break;
  }
  return std::max(0.0, 1 - std::exp(log_prefix) * h);
}

double gamma_quantile(double a, double p) {
  // P(a, x) is increasing in x: bracket, then bisect to double precision.
  double lo = 0, hi = std::max(1.0, a);
  while (regularized_gamma_p(a, hi) < p) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = (lo + hi) / 2;
    (regularized_gamma_p(a, mid) < p ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

Interval poisson_interval(std::uint64_t count, double exposure) {
  const double k = static_cast<double>(count);
  // chi2_q(2k) / 2 is the gamma(k, 1) quantile q.
  const double lo = count == 0 ? 0.0 : gamma_quantile(k, 0.025);
  const double hi = gamma_quantile(k + 1, 0.975);
  return {lo / exposure, hi / exposure};
}

}  // namespace tagbench::bench
