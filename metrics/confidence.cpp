// Confidence intervals over seeds (declared in confidence.h).
#include "metrics/confidence.h"

#include <array>
#include <cmath>
#include <stdexcept>

namespace causticbench {

double student_t_975(int degrees) {
  if (degrees < 1) throw std::invalid_argument("student_t_975: at least one degree of freedom");
  // t(0.975, n) for n = 1..30 (any statistics table; these to 7 digits).
  static constexpr std::array<double, 30> kTable = {
      12.7062047, 4.3026527, 3.1824463, 2.7764451, 2.5705818, 2.4469119, 2.3646243, 2.3060041, 2.2621572, 2.2281389,
      2.2009852,  2.1788128, 2.1603687, 2.1447867, 2.1314495, 2.1199053, 2.1098155, 2.1009220, 2.0930241, 2.0859634,
      2.0796138,  2.0738731, 2.0686576, 2.0638986, 2.0595386, 2.0555294, 2.0518305, 2.0484071, 2.0452296, 2.0422725};
  if (degrees <= static_cast<int>(kTable.size())) return kTable[static_cast<size_t>(degrees - 1)];
  // Cornish-Fisher expansion of the t quantile in powers of 1/n around z = Phi^-1(0.975).
  const double z = 1.959963984540054, n = degrees;
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n);
}

MetricInterval interval_of(const std::vector<double>& values) {
  if (values.empty()) throw std::invalid_argument("interval_of: no values");
  MetricInterval interval;
  interval.count = static_cast<int>(values.size());
  double sum = 0.0;
  for (double value : values) sum += value;
  interval.mean = sum / static_cast<double>(values.size());
  if (values.size() == 1) return interval;
  double squares = 0.0;
  for (double value : values) squares += (value - interval.mean) * (value - interval.mean);
  interval.standard_deviation = std::sqrt(squares / static_cast<double>(values.size() - 1));
  interval.half_width =
      student_t_975(interval.count - 1) * interval.standard_deviation / std::sqrt(static_cast<double>(values.size()));
  return interval;
}

bool intervals_overlap(const MetricInterval& a, const MetricInterval& b) {
  return a.low() <= b.high() && b.low() <= a.high();
}

}  // namespace causticbench
