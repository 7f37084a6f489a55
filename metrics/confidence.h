// Confidence intervals of a metric over independent seeds (docs/metrics.md, "Seeds and confidence"):
// the one definition that the runner (experiments/seed_replicas.h), `report --recompute-metrics` and
// the report's "not separated" marks use. A run measured with N seeds reports the mean of its N values
// and the two-sided 95 % Student-t interval of that mean, mean ± t(0.975, N-1) · s / √N, s the sample
// standard deviation: exact for normally distributed values, and close for the means of many pixels'
// errors that the metrics are (Celarek et al. 2019 estimate expected error from many short runs the same
// way). A deterministic run's interval has zero width.
#pragma once

#include <vector>

namespace causticbench {

// The confidence of every interval the suite reports.
inline constexpr double kIntervalConfidence = 0.95;

// The 0.975 quantile of Student's t distribution with `degrees` degrees of freedom (>= 1): the standard
// table to 30 degrees, then the Cornish-Fisher expansion around the normal quantile (within 2e-6 of the
// exact value from 31 degrees on).
double student_t_975(int degrees);

struct MetricInterval {
  double mean = 0.0;
  double half_width = 0.0;          // the interval is [mean - half_width, mean + half_width]
  double standard_deviation = 0.0;  // of the values (sample, N - 1 in the denominator)
  int count = 0;                    // values it is made of; 1: a deterministic run (zero width)

  double low() const { return mean - half_width; }
  double high() const { return mean + half_width; }
  bool contains(double value) const { return value >= low() && value <= high(); }
};

// The mean and 95 % interval of `values` (at least one; one value gives zero width).
MetricInterval interval_of(const std::vector<double>& values);

// Whether two intervals share a point: the difference of their means is not established at 95 % by
// either's interval ("not separated" in reports). A conservative test: two 95 % intervals that overlap
// slightly can still differ at 95 % by a two-sample test, never the other way round.
bool intervals_overlap(const MetricInterval& a, const MetricInterval& b);

}  // namespace causticbench
