#include "common/chi_square.h"

#include <algorithm>
#include <cmath>

namespace slt {
namespace {

// Regularised lower incomplete gamma P(a, x): series below a + 1, Lentz continued fraction above.
double RegularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 500 && std::abs(term) > 1e-17 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefix);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 500; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double ChiSquareQuantile(double probability, int dof) {
  const double k = dof;
  // Wilson-Hilferty start.
  const double z = std::sqrt(2.0) * [&] {
    // inverse erf via Newton on erf, from a rough start
    double y = 0.0;
    const double target = 2.0 * probability - 1.0;
    for (int i = 0; i < 100; ++i) {
      const double err = std::erf(y) - target;
      y -= err / (2.0 / std::sqrt(M_PI) * std::exp(-y * y));
      if (std::abs(err) < 1e-15) break;
    }
    return y;
  }();
  const double h = 2.0 / (9.0 * k);
  double x = std::max(1e-6, k * std::pow(1.0 - h + z * std::sqrt(h), 3.0));
  // Newton on the CDF.
  for (int i = 0; i < 50; ++i) {
    const double cdf = RegularizedGammaP(0.5 * k, 0.5 * x);
    const double log_pdf = (0.5 * k - 1.0) * std::log(x) - 0.5 * x - 0.5 * k * std::log(2.0) - std::lgamma(0.5 * k);
    const double step = (cdf - probability) / std::exp(log_pdf);
    x = std::max(0.5 * x, x - step);
    if (std::abs(step) < 1e-12 * x) break;
  }
  return x;
}

}  // namespace slt
