// FLIP (metrics/flip.h) against ../shared/metrics/flip.md: its properties (section 8) and the values the
// reference implementation v1.6 printed for small synthetic pairs (section 9), and the `flip` metric of
// compute_metrics() on caustic-like images (section 10).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "metrics/flip.h"
#include "metrics/metrics.h"

namespace causticbench {
namespace {

// flip.md section 8: means agree with the reference to about 1e-4; the other pooled values are pixel
// values, whose per-pixel deviation is about 2e-4 relative, so 1e-4 absolute on values below 1 too.
constexpr double kTolerance = 1e-4;

// An 8-bit PNG as FLIP reads it: value / 255, sRGB-decoded.
float png(int value) { return flip_srgb_to_linear(static_cast<float>(value) / 255.0f); }

Image constant(int width, int height, float r, float g, float b) {
  Image image(width, height, 3);
  for (size_t p = 0; p < image.pixel_count(); ++p) image.set_rgb(p, Color(r, g, b));
  return image;
}

void set_grey(Image& image, int x, int y, float value) {
  image.set_rgb(static_cast<size_t>(y) * image.width() + x, Color(value, value, value));
}

Image random_image(int width, int height, uint32_t seed, float scale = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  Image image(width, height, 3);
  for (float& v : image.values()) v = scale * uniform(rng);
  return image;
}

// Pair A: grey 128 with a 16x16 block of 153.
struct PairA {
  Image reference = constant(64, 64, png(128), png(128), png(128));
  Image test = reference;
  PairA() {
    for (int y = 24; y <= 39; ++y)
      for (int x = 24; x <= 39; ++x) set_grey(test, x, y, png(153));
  }
};

// Pair B: a black-white edge at column 16 against one at column 18.
Image edge_image(int first_white_column) {
  Image image(32, 32, 3);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) set_grey(image, x, y, x < first_white_column ? png(0) : png(255));
  return image;
}

// Pair D: a log ramp from 1/16 to 16 along x, and the same with a 16x16 block twice as bright.
struct PairD {
  Image reference{64, 64, 3};
  Image test{64, 64, 3};
  PairD() {
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const float value = std::exp2(8.0f * static_cast<float>(x) / 63.0f - 4.0f);
        const bool block = x >= 24 && x <= 39 && y >= 24 && y <= 39;
        set_grey(reference, x, y, value);
        set_grey(test, x, y, block ? 2.0f * value : value);
      }
  }
};

void expect_pooled(const FlipPooled& p, double mean, double median, double q1, double q3, double max) {
  EXPECT_NEAR(p.mean, mean, kTolerance);
  EXPECT_NEAR(p.weighted_median, median, kTolerance);
  EXPECT_NEAR(p.first_weighted_quartile, q1, kTolerance);
  EXPECT_NEAR(p.third_weighted_quartile, q3, kTolerance);
  EXPECT_NEAR(p.max, max, kTolerance);
}

// flip.md section 8, property 4.
TEST(Flip, ConstantsOfTheDefaultObserver) {
  EXPECT_NEAR(FlipOptions{}.pixels_per_degree, 67.0206, 1e-4);
  EXPECT_EQ(flip_spatial_radius(kFlipDefaultPixelsPerDegree), 10);
  EXPECT_EQ(flip_feature_radius(kFlipDefaultPixelsPerDegree), 9);
  EXPECT_NEAR(flip_cmax(), 41.2761, 1e-4);
  EXPECT_NEAR(std::pow(flip_cmax(), 1.0 / 0.7), 203.3017, 1e-2);
  EXPECT_NEAR(flip_tone_mapper_xmax(FlipToneMapper::aces), 2.118872, 1e-5);
  EXPECT_NEAR(flip_tone_mapper_xmax(FlipToneMapper::reinhard), 5.666667, 1e-5);
  // The sRGB decode of section 1.
  EXPECT_FLOAT_EQ(flip_srgb_to_linear(0.04f), 0.04f / 12.92f);
  EXPECT_NEAR(flip_srgb_to_linear(128.0f / 255.0f), 0.2158605, 1e-6);
}

TEST(Flip, IdenticalImagesGiveExactlyZero) {
  Image image = random_image(40, 30, 7);
  Image ldr = flip_error_map_ldr(image, image);
  for (float v : ldr.values()) ASSERT_EQ(v, 0.0f);

  Image hdr_image = random_image(40, 30, 8, 20.0f);
  HdrFlipResult hdr = flip_error_map_hdr(hdr_image, hdr_image);
  EXPECT_GE(hdr.exposures.count, 2);
  for (float v : hdr.error_map.values()) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(flip_pool(hdr.error_map).mean, 0.0);
}

TEST(Flip, MapValuesLieInTheUnitInterval) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    Image reference = random_image(48, 40, seed), test = random_image(48, 40, 100 + seed);
    Image map = flip_error_map_ldr(reference, test);
    ASSERT_EQ(map.channels(), 1);
    ASSERT_EQ(map.pixel_count(), reference.pixel_count());
    for (float v : map.values()) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
    }
    EXPECT_GT(flip_pool(map).mean, 0.1) << "random pairs differ a lot";

    HdrFlipResult hdr = flip_error_map_hdr(random_image(48, 40, seed, 50.0f), random_image(48, 40, 200 + seed, 50.0f));
    for (size_t p = 0; p < hdr.error_map.pixel_count(); ++p) {
      ASSERT_GE(hdr.error_map.at(p, 0), 0.0f);
      ASSERT_LE(hdr.error_map.at(p, 0), 1.0f);
      ASSERT_GE(hdr.exposure_map.at(p, 0), 0.0f);
      ASSERT_LE(hdr.exposure_map.at(p, 0), 1.0f);
    }
  }
  // Pure green against pure blue, the largest colour difference: Ec = 1, so E = 1.
  Image green = constant(16, 16, 0, 1, 0), blue = constant(16, 16, 0, 0, 1);
  EXPECT_NEAR(flip_pool(flip_error_map_ldr(green, blue)).max, 1.0, 1e-5);
}

// flip.md section 9, pair A.
TEST(Flip, SanityPairA) {
  PairA a;
  expect_pooled(flip_pool(flip_error_map_ldr(a.reference, a.test)), 0.027298, 0.344433, 0.317310, 0.370448,
                0.377630);
}

// Pair B, and section 8 property 5: LDR-FLIP is symmetric.
TEST(Flip, SanityPairBAndSymmetry) {
  Image reference = edge_image(16), test = edge_image(18);
  Image forward = flip_error_map_ldr(reference, test), backward = flip_error_map_ldr(test, reference);
  expect_pooled(flip_pool(forward), 0.166797, 0.812341, 0.589271, 0.970655, 0.975001);
  EXPECT_NEAR(flip_pool(backward).mean, 0.166797, kTolerance);
  for (size_t p = 0; p < forward.pixel_count(); ++p) ASSERT_NEAR(forward.at(p, 0), backward.at(p, 0), 1e-6) << p;
}

// Pair C, and section 8 property 3: constant images give a constant map, the colour error of the pair.
TEST(Flip, SanityPairCConstantImagesGiveAConstantMap) {
  Image reference = constant(32, 32, png(128), png(128), png(128));
  Image test = constant(32, 32, png(140), png(128), png(110));
  Image map = flip_error_map_ldr(reference, test);
  for (size_t p = 0; p < map.pixel_count(); ++p) {
    ASSERT_EQ(map.at(p, 0), map.at(0, 0)) << "pixel " << p;
    ASSERT_NEAR(map.at(p, 0), 0.220971, kTolerance) << "pixel " << p;
  }
  EXPECT_NEAR(flip_pool(map).mean, 0.220973, kTolerance);
}

// Pair D (HDR) with its automatic exposure range, and section 8 property 5: swapped, the range changes.
TEST(Flip, SanityPairDHdrAndItsAsymmetry) {
  PairD d;
  HdrFlipResult hdr = flip_error_map_hdr(d.reference, d.test);
  EXPECT_NEAR(hdr.exposures.start, -2.9167, kTolerance);
  EXPECT_NEAR(hdr.exposures.stop, 1.0198, kTolerance);
  EXPECT_EQ(hdr.exposures.count, 4);
  expect_pooled(flip_pool(hdr.error_map), 0.042645, 0.543549, 0.471813, 0.553054, 0.601543);

  HdrFlipResult swapped = flip_error_map_hdr(d.test, d.reference);
  EXPECT_NEAR(swapped.exposures.stop, 0.7817, kTolerance);
  EXPECT_NEAR(flip_pool(swapped.error_map).mean, 0.042657, kTolerance);

  // Set bounds are kept; the count follows them; a start above the stop is refused.
  FlipOptions options;
  options.start_exposure = -1.0f;
  FlipExposureRange range = flip_exposure_range(d.reference, options);
  EXPECT_EQ(range.start, -1.0f);
  EXPECT_NEAR(range.stop, 1.0198, kTolerance);
  EXPECT_EQ(range.count, 3);
  options.start_exposure = 2.0f;
  EXPECT_THROW(flip_exposure_range(d.reference, options), std::invalid_argument);
}

// The section 9 row "any: an image against itself gives 0.000000", on an image with structure.
TEST(Flip, SanityIdenticalPairsPoolToZero) {
  PairA a;
  PairD d;
  EXPECT_EQ(flip_pool(flip_error_map_ldr(a.test, a.test)).mean, 0.0);
  EXPECT_EQ(flip_pool(flip_error_map_hdr(d.test, d.test).error_map).mean, 0.0);
}

TEST(Flip, WeightedPercentileFollowsTheSpecification) {
  // Sorted 0.1 0.2 0.3 0.4, total 1: running sums 0.1 0.3 0.6 1.0.
  EXPECT_FLOAT_EQ(static_cast<float>(flip_weighted_percentile({0.4f, 0.1f, 0.3f, 0.2f}, 0.5)), 0.3f);
  EXPECT_FLOAT_EQ(static_cast<float>(flip_weighted_percentile({0.4f, 0.1f, 0.3f, 0.2f}, 0.25)), 0.2f);
  EXPECT_EQ(flip_weighted_percentile({0.0f, 0.0f}, 0.5), 0.0);
}

// Section 3: the separable CSF filter equals a direct 2D convolution with the normalised 2D kernel
// S(sqrt(x^2 + y^2)) over the (2 rs + 1)^2 window, clamp-to-edge. The image is smaller than the window,
// so the borders are exercised everywhere.
TEST(Flip, SeparableCsfFilterEqualsTheDirect2DConvolution) {
  const float ppd = kFlipDefaultPixelsPerDegree;
  const int width = 23, height = 17, r = flip_spatial_radius(ppd);
  Image ycxcz = flip_linear_rgb_to_ycxcz(random_image(width, height, 42));
  Image separable = flip_csf_filter(ycxcz, ppd);

  struct Csf {
    double a1, b1, a2, b2;
  };
  const Csf csf[3] = {{1, 0.0047, 0, 1e-5}, {1, 0.0053, 0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};
  const double pi = 3.14159265358979323846;
  for (int c = 0; c < 3; ++c) {
    auto S = [&](double r2) {
      return csf[c].a1 * std::sqrt(pi / csf[c].b1) * std::exp(-pi * pi * r2 / csf[c].b1) +
             csf[c].a2 * std::sqrt(pi / csf[c].b2) * std::exp(-pi * pi * r2 / csf[c].b2);
    };
    std::vector<double> kernel;
    double sum = 0.0;
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i) {
        kernel.push_back(S((i * i + j * j) / (static_cast<double>(ppd) * ppd)));
        sum += kernel.back();
      }
    double largest_difference = 0.0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double direct = 0.0;
        size_t k = 0;
        for (int j = -r; j <= r; ++j)
          for (int i = -r; i <= r; ++i, ++k) {
            const int sx = std::clamp(x + i, 0, width - 1), sy = std::clamp(y + j, 0, height - 1);
            direct += kernel[k] / sum * ycxcz.at(static_cast<size_t>(sy) * width + sx, c);
          }
        const double got = separable.at(static_cast<size_t>(y) * width + x, c);
        largest_difference = std::max(largest_difference, std::abs(got - direct));
        // float32 rounding on values up to about 100 (Y') and 200 (Cx, Cz).
        ASSERT_NEAR(got, direct, 2e-4 * (1.0 + std::abs(direct))) << "channel " << c << " at " << x << "," << y;
      }
    EXPECT_GT(largest_difference, 0.0) << "the filter ran (not a copy of the input)";
  }
}

// --- The `flip` metric on E_c ---------------------------------------------------------------------------

// A receiver disc with a bright off-centre blob on a black floor, like a caustic: exactly 0 more than 6
// pixels from the blob's centre, so most receiver pixels are black.
double blob(int x, int y, double cx, double cy) {
  const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
  return d2 > 36.0 ? 0.0 : 40.0 * std::exp(-d2 / 8.0);
}

// The test is the blob moved by 3 pixels.
struct CausticCase {
  static constexpr int kSize = 48;
  Image reference{kSize, kSize, 3};
  Image test{kSize, kSize, 3};
  std::vector<uint8_t> mask = std::vector<uint8_t>(kSize * kSize, 0);
  CausticCase() {
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const size_t p = static_cast<size_t>(y) * kSize + x;
        const double dx = x - 24.0, dy = y - 24.0;
        mask[p] = dx * dx + dy * dy < 20.0 * 20.0;
        set_grey(reference, x, y, static_cast<float>(blob(x, y, 20.0, 26.0)));
        set_grey(test, x, y, static_cast<float>(blob(x, y, 23.0, 26.0)));
      }
  }
};

TEST(FlipMetric, RegisteredAsLowerIsBetterAndPerFrame) {
  const MetricInfo& info = find_metric("flip");
  EXPECT_FALSE(info.higher_is_better);
  EXPECT_FALSE(info.target.has_value());
  EXPECT_EQ(info.unit, "");
  EXPECT_TRUE(info.per_frame);
  EXPECT_EQ(info.definition.find('\n'), std::string::npos);
}

TEST(FlipMetric, PixelsOutsideTheMaskDoNotChangeTheValue) {
  CausticCase s;
  MetricValues before = compute_metrics(s.test, s.reference, s.mask, {"flip"});
  ASSERT_TRUE(before.values.count("flip")) << before.undefined["flip"];
  const double value = before.values.at("flip");
  EXPECT_GT(value, 0.0);
  EXPECT_LE(value, 1.0);
  EXPECT_GE(before.parameters.at("flip").at("exposures"), 2.0);
  EXPECT_LE(before.parameters.at("flip").at("start_exposure"), before.parameters.at("flip").at("stop_exposure"));
  EXPECT_NEAR(before.parameters.at("flip").at("pixels_per_degree"), 67.0206, 1e-4);

  Image test = s.test, reference = s.reference;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(0.0f, 1000.0f);
  for (size_t p = 0; p < s.mask.size(); ++p) {
    if (s.mask[p]) continue;
    for (int c = 0; c < 3; ++c) {
      test.at(p, c) = uniform(rng);
      reference.at(p, c) = p % 7 == 0 ? std::numeric_limits<float>::quiet_NaN() : uniform(rng);
    }
  }
  MetricValues after = compute_metrics(test, reference, s.mask, {"flip"});
  ASSERT_TRUE(after.values.count("flip"));
  EXPECT_EQ(after.values.at("flip"), value);
  EXPECT_EQ(after.parameters.at("flip"), before.parameters.at("flip"));

  // The same pixels, counted: the value does change (the mask is what keeps them out).
  std::vector<uint8_t> everything(s.mask.size(), 1);
  Image finite_reference = s.reference;
  MetricValues all = compute_metrics(test, finite_reference, everything, {"flip"});
  EXPECT_NE(all.values.at("flip"), value);
}

TEST(FlipMetric, UndefinedForAnAllZeroReference) {
  CausticCase s;
  Image zero(CausticCase::kSize, CausticCase::kSize, 3, 0.0f);
  MetricValues m = compute_metrics(s.test, zero, s.mask, {"flip", "mse"});
  EXPECT_FALSE(m.values.count("flip"));
  ASSERT_TRUE(m.undefined.count("flip"));
  EXPECT_NE(m.undefined.at("flip").find("reference is 0"), std::string::npos) << m.undefined.at("flip");
  EXPECT_TRUE(m.values.count("mse"));
  EXPECT_FALSE(m.parameters.count("flip"));
  EXPECT_TRUE(compute_metrics(zero, zero, s.mask, {"flip"}).undefined.count("flip")) << "0 / 0";
  MetricValues black_test = compute_metrics(zero, s.reference, s.mask, {"flip"});
  ASSERT_TRUE(black_test.values.count("flip")) << "0 / x is defined: the exposures come from the reference";
  EXPECT_GT(black_test.values.at("flip"), 0.0);

  // Light only outside the mask is no light.
  Image outside = zero;
  for (size_t p = 0; p < s.mask.size(); ++p)
    if (!s.mask[p]) outside.set_rgb(p, Color(5, 5, 5));
  EXPECT_TRUE(compute_metrics(s.test, outside, s.mask, {"flip"}).undefined.count("flip"));
  EXPECT_TRUE(caustic_flip(s.test, zero, s.mask).error_map.values().empty());
}

TEST(FlipMetric, NonFiniteTestPixelsAreZeroedAndLeftOut) {
  CausticCase s;
  Image test = s.test;
  const size_t bad = static_cast<size_t>(26) * CausticCase::kSize + 22;  // inside the blob
  ASSERT_TRUE(s.mask[bad]);
  test.at(bad, 1) = std::numeric_limits<float>::quiet_NaN();
  MetricValues m = compute_metrics(test, s.reference, s.mask, {"flip", "nonfinite_pixels"});
  EXPECT_EQ(m.nonfinite_pixels, 1u);
  ASSERT_TRUE(m.values.count("flip"));
  EXPECT_TRUE(std::isfinite(m.values.at("flip")));

  // Equal to the map of the test with that pixel black, pooled without it.
  Image zeroed = s.test;
  zeroed.set_rgb(bad, Color(0, 0, 0));
  CausticFlip black = caustic_flip(zeroed, s.reference, s.mask);
  std::vector<uint8_t> without = s.mask;
  without[bad] = 0;
  EXPECT_NEAR(m.values.at("flip"), flip_pool(black.error_map, without).mean, 1e-12);

  Image all_nan = s.test;
  for (float& v : all_nan.values()) v = std::numeric_limits<float>::infinity();
  MetricValues none = compute_metrics(all_nan, s.reference, s.mask, {"flip"});
  EXPECT_TRUE(none.undefined.count("flip"));
}

// flip.md section 10: on a mostly black reference the whole-image median is 0, the reference tool's stop
// exposure is infinite and its mean 0; the receiver rule gives a finite range and a real error.
TEST(FlipMetric, MostlyBlackReferenceGivesAFiniteNonTrivialValue) {
  CausticCase s;
  EXPECT_FALSE(std::isfinite(flip_exposure_range(s.reference).stop));
  EXPECT_THROW(flip_error_map_hdr(s.reference, s.test), std::invalid_argument);

  CausticFlip wrong = caustic_flip(s.test, s.reference, s.mask);
  ASSERT_TRUE(wrong.defined()) << wrong.undefined_reason;
  EXPECT_TRUE(std::isfinite(wrong.exposures.start));
  EXPECT_TRUE(std::isfinite(wrong.exposures.stop));
  EXPECT_GE(wrong.exposures.stop, wrong.exposures.start);
  EXPECT_GE(wrong.exposures.count, 2);
  EXPECT_LE(wrong.exposures.count, 10);
  EXPECT_GT(wrong.mean, 0.02) << "a blob moved by 3 pixels is visibly wrong";

  // A flat grey guess of the same mean is wrong too; the reference itself is exact.
  Image grey(CausticCase::kSize, CausticCase::kSize, 3, 0.5f);
  EXPECT_GT(caustic_flip(grey, s.reference, s.mask).mean, wrong.mean);
  EXPECT_EQ(caustic_flip(s.reference, s.reference, s.mask).mean, 0.0);
  EXPECT_EQ(flip_error_map(s.test, s.reference, s.mask).pixel_count(), s.reference.pixel_count());
}

// Issue 50, item 8: every finite non-negative image a method may write is scored, however bright. A constant
// 1e25 W/m^2 image once scored FLIP 0 (the tone curve's x^2 overflowed float, and a clamp keeps NaN): it
// saturates every exposure exactly as a constant 1e6 does, so their maps are equal, and far from 0.
TEST(FlipMetric, HugeFiniteImagesScoreAsSaturatedNotAsPerfect) {
  CausticCase s;
  const double saturated = caustic_flip(Image(CausticCase::kSize, CausticCase::kSize, 3, 1e6f), s.reference, s.mask).mean;
  EXPECT_GT(saturated, 0.3) << "a white image against a caustic";
  for (float value : {1e20f, 1e25f, 1e30f, std::numeric_limits<float>::max()}) {
    SCOPED_TRACE(value);
    const Image huge(CausticCase::kSize, CausticCase::kSize, 3, value);
    MetricValues m = compute_metrics(huge, s.reference, s.mask, {"flip", "relmse", "energy_ratio"});
    ASSERT_TRUE(m.values.count("flip"));
    EXPECT_EQ(m.values.at("flip"), saturated);
    EXPECT_TRUE(std::isfinite(m.values.at("relmse")));
    EXPECT_GT(m.values.at("relmse"), 1e20);
    // Every map value is finite and in [0, 1], under each tone mapper.
    for (FlipToneMapper mapper : {FlipToneMapper::aces, FlipToneMapper::hable, FlipToneMapper::reinhard}) {
      FlipOptions options;
      options.tone_mapper = mapper;
      CausticFlip flip = caustic_flip(huge, s.reference, s.mask, options);
      for (float v : flip.error_map.values()) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
      EXPECT_GT(flip.mean, 0.3);
    }
  }
}

// A benchmark, not a test (it asserts nothing, so CTest does not run it): HDR-FLIP runs for every stored
// run, and its cost is printed by
//   build/tests/test_flip --gtest_also_run_disabled_tests --gtest_filter='FlipTiming.*'
TEST(FlipTiming, DISABLED_HdrFlipOn256And512) {
  for (int size : {256, 512}) {
    // Luminances spread over 12 stops, as in a caustic: about 6 exposures.
    Image reference = random_image(size, size, 11), test = random_image(size, size, 12);
    for (Image* image : {&reference, &test})
      for (float& v : image->values()) v = std::exp2(12.0f * v - 8.0f);
    std::vector<uint8_t> mask(reference.pixel_count(), 1);
    auto start = std::chrono::steady_clock::now();
    CausticFlip result = caustic_flip(test, reference, mask);
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ timing ] HDR-FLIP %dx%d: %.1f ms, %d exposures (%.2f ms per exposure)\n", size, size, ms,
                result.exposures.count, ms / result.exposures.count);
  }
}

}  // namespace
}  // namespace causticbench
