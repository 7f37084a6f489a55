// The randomised Sobol points of the photon tracer's stratified emission (core/low_discrepancy.h): the
// net properties that make them stratify, the uniformity that keeps estimates unbiased, and the variance
// they save on a discontinuous integrand such as a pixel's share of a caustic. Links only the core.
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "core/low_discrepancy.h"

namespace causticbench {
namespace {

// Every one of the 2^m elementary intervals of length 2^-m holds exactly one of the first 2^m points of
// each dimension (a (0, m, 1)-net), also after a digital shift.
TEST(LowDiscrepancy, EveryDimensionStratifiesItsPrefixes) {
  const int m = 12;
  const uint32_t count = 1u << m;
  for (int dimension = 0; dimension < kSobolDimensions; ++dimension) {
    for (uint64_t pass : {0ull, 7ull}) {
      ShiftedSobol points(3, pass);
      std::set<uint32_t> cells;
      for (uint32_t i = 0; i < count; ++i) cells.insert(static_cast<uint32_t>(points.uniform(i, dimension) * count));
      EXPECT_EQ(cells.size(), count) << "dimension " << dimension << " pass " << pass;
    }
    std::set<uint32_t> unshifted;
    for (uint32_t i = 0; i < count; ++i) unshifted.insert(sobol_bits(i, dimension) >> (32 - m));
    EXPECT_EQ(unshifted.size(), count) << "dimension " << dimension;
  }
}

// The two dimensions the emission aims with (the disk or cone: 0 and 1) form a (0, m, 2)-net: every box
// of 2^-k by 2^-(m-k) holds exactly one of the first 2^m points, for every k; shifted ones too.
TEST(LowDiscrepancy, TheAimingDimensionsAreAZeroNet) {
  const int m = 10;
  const uint32_t count = 1u << m;
  ShiftedSobol points(11, 2);
  for (int k = 0; k <= m; ++k) {
    std::set<std::pair<uint32_t, uint32_t>> boxes;
    for (uint32_t i = 0; i < count; ++i)
      boxes.insert({static_cast<uint32_t>(points.uniform(i, 0) * (1u << k)),
                    static_cast<uint32_t>(points.uniform(i, 1) * (1u << (m - k)))});
    EXPECT_EQ(boxes.size(), count) << "boxes of 2^-" << k << " x 2^-" << (m - k);
  }
}

// Over independent passes, one point's coordinate is uniform (the shift is): the fraction of passes in
// which it falls below 0.3 is 0.3 within four standard deviations (fixed seeds; a 6e-5 chance for
// arbitrary ones), in every dimension.
TEST(LowDiscrepancy, AShiftedPointIsUniformOverPasses) {
  const int passes = 20000;
  for (int dimension = 0; dimension < kSobolDimensions; ++dimension) {
    int below = 0;
    for (int pass = 0; pass < passes; ++pass) below += ShiftedSobol(5, static_cast<uint64_t>(pass)).uniform(37, dimension) < 0.3f;
    const double sigma = std::sqrt(0.3 * 0.7 / passes);
    EXPECT_NEAR(static_cast<double>(below) / passes, 0.3, 4.0 * sigma) << "dimension " << dimension;
  }
}

// The estimate of a disk's area (a pixel's preimage on the emission disk has such an edge) from 4096
// points: over 400 passes, its mean is the area (unbiased, within four standard errors) and its variance
// is far below the binomial p (1 - p) / N of independent points (measured about 1/60 of it; asserted
// below a quarter).
TEST(LowDiscrepancy, StratifiedPointsEstimateADiscontinuousIntegralWithLessVariance) {
  const uint32_t count = 4096;
  const int passes = 400;
  const double radius = 0.3, area = M_PI * radius * radius;
  double sum = 0.0, squares = 0.0;
  for (int pass = 0; pass < passes; ++pass) {
    ShiftedSobol points(9, static_cast<uint64_t>(pass));
    int inside = 0;
    for (uint32_t i = 0; i < count; ++i) {
      const double x = points.uniform(i, 0) - 0.5, y = points.uniform(i, 1) - 0.5;
      inside += x * x + y * y < radius * radius;
    }
    const double estimate = static_cast<double>(inside) / count;
    sum += estimate;
    squares += estimate * estimate;
  }
  const double mean = sum / passes, variance = (squares / passes - mean * mean) * passes / (passes - 1.0);
  const double independent = area * (1.0 - area) / count;
  EXPECT_NEAR(mean, area, 4.0 * std::sqrt(variance / passes));
  EXPECT_LT(variance, 0.25 * independent) << "variance " << variance << " against " << independent << " independent";
}

}  // namespace
}  // namespace causticbench
