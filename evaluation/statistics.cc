#include "evaluation/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slt {

double Quantile(std::vector<double> values, double p) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1.0) * std::clamp(p, 0.0, 1.0);
  const size_t lo = static_cast<size_t>(std::floor(h));
  const size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (h - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

Summary Summarize(const std::vector<double>& values) {
  std::vector<double> finite;
  finite.reserve(values.size());
  for (double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  Summary s;
  s.count = finite.size();
  if (finite.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.mean = s.median = s.p2_5 = s.p97_5 = nan;
    return s;
  }
  double sum = 0.0;
  for (double v : finite) sum += v;
  s.mean = sum / static_cast<double>(finite.size());
  s.median = Quantile(finite, 0.5);
  s.p2_5 = Quantile(finite, 0.025);
  s.p97_5 = Quantile(finite, 0.975);
  return s;
}

ErrorStatistics ComputeStatistics(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("statistics of an empty set of errors");
  ErrorStatistics s;
  s.count = values.size();
  const double n = static_cast<double>(values.size());
  double sum = 0.0, sum_squares = 0.0;
  for (double v : values) {
    sum += v;
    sum_squares += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_squares / n);
  double squared_deviations = 0.0;
  for (double v : values) squared_deviations += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(squared_deviations / n);
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  const size_t half = values.size() / 2;
  s.median = values.size() % 2 == 1 ? values[half] : 0.5 * (values[half - 1] + values[half]);
  return s;
}

}  // namespace slt
