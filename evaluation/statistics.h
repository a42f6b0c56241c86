// Statistics of a set of values, the one module for them: the summary over trials (mean, median,
// 95 % interval) of the experiments and the error statistics of a trajectory (evo's).
#pragma once

#include <cstddef>
#include <vector>

namespace slt {

// The p-th quantile (0 <= p <= 1) of `values` with linear interpolation between order
// statistics: sorted x_0 <= ... <= x_{n-1}, h = (n - 1) p, q = x_floor(h) + (h - floor(h))
// (x_floor(h)+1 - x_floor(h)). This is numpy's default ("linear", Hyndman & Fan type 7).
// NaN for an empty set.
double Quantile(std::vector<double> values, double p);

struct Summary {
  size_t count = 0;  // finite values summarised
  double mean = 0.0;
  double median = 0.0;
  double p2_5 = 0.0;   // 2.5th percentile: lower end of the 95 % interval
  double p97_5 = 0.0;  // 97.5th percentile: upper end
};

// Non-finite values are left out (count says how many were used); all NaN when none is left.
Summary Summarize(const std::vector<double>& values);

// Summary of a set of errors, as evo prints it. std is the population standard deviation.
struct ErrorStatistics {
  size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;  // mean of the two middle values for an even count
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
};
// Throws std::invalid_argument on an empty set.
ErrorStatistics ComputeStatistics(std::vector<double> values);

}  // namespace slt
