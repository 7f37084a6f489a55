// Metrics on tiny synthetic images with hand-computed values (docs/metrics.md has the definitions).
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/image_statistics.h"
#include "metrics/metrics.h"

namespace causticbench {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

using Pixel = std::array<float, 3>;

Image row_image(const std::vector<Pixel>& pixels) {
  Image image(static_cast<int>(pixels.size()), 1);
  for (size_t p = 0; p < pixels.size(); ++p)
    for (int c = 0; c < 3; ++c) image.at(p, c) = pixels[p][c];
  return image;
}

const std::vector<std::string> kPerFrame = {"mse",          "rmse",      "psnr",  "ssim", "relmse",
                                            "energy_ratio", "max_error", "nonfinite_pixels"};

// Four pixels, the last one outside the mask; pixel 1 has a zero reference.
//   p0: reference (1, 2, 3), test (1.5, 2, 2)  -> differences (0.5, 0, -1)
//   p1: reference (0, 0, 0), test (0.3, 0, 0)  -> differences (0.3, 0, 0)
//   p2: reference (2, 2, 2), test (2, 2, 2)    -> no difference
//   p3: unmasked, wildly different
struct SmallCase {
  Image test = row_image({{1.5f, 2.0f, 2.0f}, {0.3f, 0.0f, 0.0f}, {2.0f, 2.0f, 2.0f}, {100.0f, -5.0f, 7.0f}});
  Image reference = row_image({{1.0f, 2.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, {2.0f, 2.0f, 2.0f}, {1.0f, 1.0f, 1.0f}});
  std::vector<uint8_t> mask = {1, 1, 1, 0};
};

TEST(Metrics, HandComputedValuesOnMaskedPixels) {
  SmallCase s;
  MetricValues m = compute_metrics(s.test, s.reference, s.mask, kPerFrame);

  const double mse = (0.25 + 1.0 + 0.09) / 9.0;  // 3 pixels x 3 channels
  EXPECT_NEAR(m.values.at("mse"), mse, 1e-7);
  EXPECT_NEAR(m.values.at("rmse"), std::sqrt(mse), 1e-7);
  EXPECT_NEAR(m.values.at("max_error"), 1.0, 1e-7);
  // Peak = largest masked reference channel = 3 (the unmasked pixel does not count).
  EXPECT_NEAR(m.values.at("psnr"), 10.0 * std::log10(9.0 / mse), 1e-5);
  EXPECT_NEAR(m.values.at("psnr"), 17.81374, 1e-4);
  // Channel-mean sums: test (5.5 + 0.3 + 6) / 3, reference (6 + 0 + 6) / 3.
  EXPECT_NEAR(m.values.at("energy_ratio"), 11.8 / 12.0, 1e-7);
  EXPECT_EQ(m.values.at("nonfinite_pixels"), 0.0);
  EXPECT_EQ(m.nonfinite_pixels, 0u);
  for (const std::string& name : kPerFrame) EXPECT_TRUE(m.values.count(name)) << name;
}

TEST(Metrics, RelMseUsesTheRelativeEpsilonAndAgreesWithCore) {
  SmallCase s;
  MetricValues m = compute_metrics(s.test, s.reference, s.mask, {"relmse"});
  // Masked mean of the reference: (6 + 0 + 6) / 3 channels / 3 pixels = 4/3, eps = (0.1 * 4/3)^2.
  const double eps = (0.4 / 3.0) * (0.4 / 3.0);
  // The zero-reference pixel contributes 0.09 / eps (= 5.0625), not 0.09 / 0 or 0.09 / 1e-20.
  const double expected = (0.25 / (1.0 + eps) + 1.0 / (9.0 + eps) + 0.09 / eps) / 9.0;
  EXPECT_NEAR(m.values.at("relmse"), expected, 1e-6);
  EXPECT_NEAR(m.values.at("relmse"), 0.602114, 1e-5);
  EXPECT_DOUBLE_EQ(m.values.at("relmse"), relative_mse(s.test, s.reference, s.mask));
  EXPECT_EQ(m.values.size(), 2u);  // relmse and the always-present nonfinite_pixels
}

TEST(Metrics, UnmaskedPixelWouldChangeEveryAnswer) {
  SmallCase s;
  MetricValues masked = compute_metrics(s.test, s.reference, s.mask, kPerFrame);
  MetricValues all = compute_metrics(s.test, s.reference, {1, 1, 1, 1}, kPerFrame);
  for (const char* name : {"mse", "rmse", "psnr", "relmse", "energy_ratio", "max_error"})
    EXPECT_GT(std::abs(masked.values.at(name) - all.values.at(name)), 1e-3) << name;
  // Garbage, even non-finite, outside the mask changes nothing.
  s.test.at(3, 0) = kNaN;
  s.reference.at(3, 1) = kInf;
  MetricValues garbage = compute_metrics(s.test, s.reference, s.mask, kPerFrame);
  EXPECT_EQ(garbage.nonfinite_pixels, 0u);
  for (const std::string& name : kPerFrame) EXPECT_EQ(garbage.values.at(name), masked.values.at(name)) << name;
}

TEST(Metrics, NonFinitePixelsAreCountedAndExcluded) {
  SmallCase s;
  // Two extra masked pixels: an infinite and a NaN test pixel. Their reference values (a 5 would raise
  // the PSNR peak) must not count either.
  Image test = row_image({{1.5f, 2.0f, 2.0f},
                          {0.3f, 0.0f, 0.0f},
                          {2.0f, 2.0f, 2.0f},
                          {100.0f, -5.0f, 7.0f},
                          {kInf, 0.0f, 0.0f},
                          {kNaN, 1.0f, 1.0f}});
  Image reference = row_image({{1.0f, 2.0f, 3.0f},
                               {0.0f, 0.0f, 0.0f},
                               {2.0f, 2.0f, 2.0f},
                               {1.0f, 1.0f, 1.0f},
                               {1.0f, 1.0f, 1.0f},
                               {5.0f, 5.0f, 5.0f}});
  MetricValues with = compute_metrics(test, reference, {1, 1, 1, 0, 1, 1}, kPerFrame);
  MetricValues without = compute_metrics(test, reference, {1, 1, 1, 0, 0, 0}, kPerFrame);
  MetricValues small = compute_metrics(s.test, s.reference, s.mask, kPerFrame);
  EXPECT_EQ(with.nonfinite_pixels, 2u);
  EXPECT_EQ(with.values.at("nonfinite_pixels"), 2.0);
  EXPECT_EQ(without.nonfinite_pixels, 0u);
  for (const std::string& name : kPerFrame) {
    if (name == "nonfinite_pixels") continue;
    EXPECT_TRUE(std::isfinite(with.values.at(name))) << name;
    EXPECT_DOUBLE_EQ(with.values.at(name), without.values.at(name)) << name;
    if (name != "ssim") {  // the SSIM window sees different neighbours in the 4-pixel image
      EXPECT_DOUBLE_EQ(with.values.at(name), small.values.at(name)) << name;
    }
  }
}

TEST(Metrics, AllMaskedPixelsNonFiniteLeavesEveryOtherMetricUndefined) {
  Image test = row_image({{kNaN, 0.0f, 0.0f}, {0.0f, -kInf, 0.0f}, {1.0f, 1.0f, 1.0f}});
  Image reference = row_image({{1.0f, 1.0f, 1.0f}, {2.0f, 2.0f, 2.0f}, {1.0f, 1.0f, 1.0f}});
  MetricValues m = compute_metrics(test, reference, {1, 1, 0}, kPerFrame);
  EXPECT_EQ(m.nonfinite_pixels, 2u);
  EXPECT_EQ(m.values.at("nonfinite_pixels"), 2.0);
  EXPECT_EQ(m.values.size(), 1u);
  for (const std::string& name : kPerFrame) {
    if (name != "nonfinite_pixels") {
      EXPECT_EQ(m.undefined.at(name), "no receiver pixel with a finite test value") << name;
    }
  }
}

TEST(Metrics, PsnrWithKnownPeakAndIdenticalImages) {
  // Peak 4, every channel off by 0.4: mse = 0.16, psnr = 10 log10(16 / 0.16) = 20 dB.
  Image reference = row_image({{4.0f, 1.0f, 2.0f}, {0.0f, 3.0f, 1.0f}});
  Image test = row_image({{3.6f, 1.4f, 2.4f}, {0.4f, 2.6f, 0.6f}});
  MetricValues m = compute_metrics(test, reference, {1, 1}, {"psnr", "mse", "max_error"});
  EXPECT_NEAR(m.values.at("mse"), 0.16, 1e-6);
  EXPECT_NEAR(m.values.at("psnr"), 20.0, 1e-4);
  EXPECT_NEAR(m.values.at("max_error"), 0.4, 1e-6);

  MetricValues same = compute_metrics(reference, reference, {1, 1}, kPerFrame);
  EXPECT_EQ(same.values.at("psnr"), std::numeric_limits<double>::infinity());
  EXPECT_EQ(same.values.at("mse"), 0.0);
  EXPECT_EQ(same.values.at("relmse"), 0.0);
  EXPECT_EQ(same.values.at("energy_ratio"), 1.0);
  EXPECT_EQ(same.values.at("max_error"), 0.0);
  EXPECT_NEAR(same.values.at("ssim"), 1.0, 1e-12);
}

TEST(Metrics, EnergyRatioEdgeCases) {
  Image black = row_image({{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}});
  Image lit = row_image({{3.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 3.0f}});
  Image half = row_image({{1.5f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.5f}});
  // A reference with no caustic flux has no ratio, whatever the test holds: never 1 ("perfect") for 0/0.
  for (const Image* test : {&black, &lit}) {
    MetricValues m = compute_metrics(*test, black, {1, 1}, {"energy_ratio"});
    EXPECT_EQ(m.values.count("energy_ratio"), 0u);
    EXPECT_NE(m.undefined.at("energy_ratio").find("flux over the receivers is 0"), std::string::npos);
  }
  EXPECT_EQ(compute_metrics(black, lit, {1, 1}, {"energy_ratio"}).values.at("energy_ratio"), 0.0);
  EXPECT_NEAR(compute_metrics(half, lit, {1, 1}, {"energy_ratio"}).values.at("energy_ratio"), 0.5, 1e-12);
  EXPECT_NEAR(compute_metrics(lit, half, {1, 1}, {"energy_ratio"}).values.at("energy_ratio"), 2.0, 1e-12);
}

// Every metric on the three pairs an empty reference makes, written test/reference: 0/0 (a method that
// agrees with an empty reference), 0/x (a method that misses the caustic) and x/0 (a method with light
// where the reference has none). Metrics in the units of E_c (mse, rmse, max_error) and the count of
// non-finite pixels always have a value; those normalised by the reference (psnr by its peak, ssim by its
// range, relmse by its mean, energy_ratio by its flux, temporal_flicker by its mean) are undefined when the
// reference is 0, whatever the test holds, so 0/0 never reads as a perfect score (docs/metrics.md).
TEST(Metrics, ValueOrUndefinedOnZeroAndNonZeroPairs) {
  const Image zero = row_image({{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}});
  const Image lit = row_image({{3.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 3.0f}});
  const std::vector<uint8_t> mask = {1, 1};
  auto defined = [](const MetricValues& m, const std::string& name) {
    EXPECT_EQ(m.values.count(name) + m.undefined.count(name), 1u) << name << ": exactly one of value and reason";
    return m.values.count(name) == 1;
  };

  MetricValues zero_zero = compute_metrics(zero, zero, mask, kPerFrame);
  for (const char* name : {"mse", "rmse", "max_error", "nonfinite_pixels"}) {
    ASSERT_TRUE(defined(zero_zero, name)) << name;
    EXPECT_EQ(zero_zero.values.at(name), 0.0) << name;
  }
  for (const char* name : {"psnr", "ssim", "relmse", "energy_ratio"}) {
    EXPECT_FALSE(defined(zero_zero, name)) << name << " must not be perfect on 0/0";
    EXPECT_NE(zero_zero.undefined.at(name).find("is 0"), std::string::npos) << zero_zero.undefined.at(name);
  }

  // 0/x: every difference is the reference, (3, 0, 0) and (0, 0, 3): mse = 18 / 6 = 3, peak 3.
  MetricValues zero_lit = compute_metrics(zero, lit, mask, kPerFrame);
  for (const std::string& name : kPerFrame) EXPECT_TRUE(defined(zero_lit, name)) << name;
  EXPECT_DOUBLE_EQ(zero_lit.values.at("mse"), 3.0);
  EXPECT_DOUBLE_EQ(zero_lit.values.at("rmse"), std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(zero_lit.values.at("max_error"), 3.0);
  EXPECT_NEAR(zero_lit.values.at("psnr"), 10.0 * std::log10(9.0 / 3.0), 1e-12);
  EXPECT_EQ(zero_lit.values.at("energy_ratio"), 0.0);
  // relMSE: mean 1, eps 0.01; the two lit channels give 9 / 9.01 each, the four dark ones 0.
  EXPECT_NEAR(zero_lit.values.at("relmse"), 2.0 * 9.0 / 9.01 / 6.0, 1e-12);
  // SSIM against a black test: C1 C2 / ((mu_r^2 + C1)(sigma_r^2 + C2)), far below 1.
  EXPECT_GE(zero_lit.values.at("ssim"), 0.0);
  EXPECT_LT(zero_lit.values.at("ssim"), 0.01);

  // x/0: the same absolute errors; nothing normalised by the reference has a scale.
  MetricValues lit_zero = compute_metrics(lit, zero, mask, kPerFrame);
  for (const char* name : {"mse", "rmse", "max_error", "nonfinite_pixels"})
    ASSERT_TRUE(defined(lit_zero, name)) << name;
  EXPECT_DOUBLE_EQ(lit_zero.values.at("mse"), 3.0);
  EXPECT_DOUBLE_EQ(lit_zero.values.at("rmse"), std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(lit_zero.values.at("max_error"), 3.0);
  EXPECT_EQ(lit_zero.values.at("nonfinite_pixels"), 0.0);
  for (const char* name : {"psnr", "ssim", "relmse", "energy_ratio"}) EXPECT_FALSE(defined(lit_zero, name)) << name;

  // Temporal flicker over two frames of each pair: undefined without reference light, 0 for a black
  // method that does not change while the (static) reference does not either.
  const std::vector<std::vector<uint8_t>> masks(2, mask);
  auto flicker = [&](const Image& test, const Image& reference) {
    return temporal_flicker({test, test}, {reference, reference}, masks);
  };
  MetricValue flicker_zero_zero = flicker(zero, zero), flicker_lit_zero = flicker(lit, zero);
  EXPECT_FALSE(flicker_zero_zero.value.has_value());
  EXPECT_FALSE(flicker_lit_zero.value.has_value());
  EXPECT_NE(flicker_zero_zero.undefined_reason.find("no scale"), std::string::npos)
      << flicker_zero_zero.undefined_reason;
  EXPECT_EQ(flicker(zero, lit).value, 0.0);
}

// 24 x 24 images with smooth structure; `mask` covers a disc, the rest is garbage.
struct SsimCase {
  static constexpr int kSize = 24;
  Image reference{kSize, kSize};
  Image test{kSize, kSize};
  std::vector<uint8_t> mask = std::vector<uint8_t>(kSize * kSize, 0);

  SsimCase() {
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        size_t p = static_cast<size_t>(y) * kSize + x;
        double value = 2.0 + std::sin(0.6 * x) * std::cos(0.45 * y) + 0.05 * x;
        for (int c = 0; c < 3; ++c) reference.at(p, c) = static_cast<float>(value * (1.0 - 0.2 * c));
        double dx = x - 11.5, dy = y - 11.5;
        mask[p] = dx * dx + dy * dy < 10.0 * 10.0 ? 1 : 0;
      }
    test = reference;
  }
};

TEST(Metrics, SsimOfIdenticalAndDifferentImages) {
  SsimCase s;
  EXPECT_NEAR(compute_metrics(s.test, s.reference, s.mask, {"ssim"}).values.at("ssim"), 1.0, 1e-12);

  // A structurally different image (a coarse checkerboard with the same mean level).
  for (int y = 0; y < SsimCase::kSize; ++y)
    for (int x = 0; x < SsimCase::kSize; ++x)
      for (int c = 0; c < 3; ++c)
        s.test.at(static_cast<size_t>(y) * SsimCase::kSize + x, c) = ((x / 3 + y / 3) % 2) ? 3.0f : 1.0f;
  double different = compute_metrics(s.test, s.reference, s.mask, {"ssim"}).values.at("ssim");
  EXPECT_LT(different, 0.9);
  EXPECT_GT(different, -1.0);
}

TEST(Metrics, SsimUsesTheReferenceMaximumAsDynamicRange) {
  // Constant images: the structure term is 1 and SSIM = (2 mu1 mu2 + C1) / (mu1^2 + mu2^2 + C1) with
  // C1 = (0.01 L)^2. Reference 2, test 1, L = 2: (2 * 1 * 0.5 + 1e-4) / (1 + 0.25 + 1e-4) after normalising.
  Image reference(8, 8, 3, 2.0f), test(8, 8, 3, 1.0f);
  std::vector<uint8_t> mask(64, 1);
  double ssim = compute_metrics(test, reference, mask, {"ssim"}).values.at("ssim");
  EXPECT_NEAR(ssim, 1.0001 / 1.2501, 1e-9);

  // Scale free: multiplying both images by 1000 changes nothing.
  SsimCase s;
  for (int y = 0; y < SsimCase::kSize; ++y)
    for (int x = 0; x < SsimCase::kSize; ++x)
      for (int c = 0; c < 3; ++c) s.test.at(static_cast<size_t>(y) * SsimCase::kSize + x, c) *= 0.7f + 0.02f * x;
  double base = compute_metrics(s.test, s.reference, s.mask, {"ssim"}).values.at("ssim");
  Image big_test = s.test, big_reference = s.reference;
  for (float& v : big_test.values()) v *= 1000.0f;
  for (float& v : big_reference.values()) v *= 1000.0f;
  EXPECT_NEAR(compute_metrics(big_test, big_reference, s.mask, {"ssim"}).values.at("ssim"), base, 1e-9);
  EXPECT_LT(base, 0.9999);
}

TEST(Metrics, SsimIgnoresUnmaskedGarbageAndExcludesNonFinitePixels) {
  SsimCase s;
  for (size_t p = 0; p < s.test.pixel_count(); ++p) s.test.at(p, 1) *= 0.8f;  // a colour shift
  MetricValues clean = compute_metrics(s.test, s.reference, s.mask, kPerFrame);
  EXPECT_LT(clean.values.at("ssim"), 1.0);

  Image test = s.test, reference = s.reference;
  for (size_t p = 0; p < test.pixel_count(); ++p) {
    if (s.mask[p]) continue;
    test.at(p, 0) = (p % 3 == 0) ? kNaN : (p % 3 == 1) ? 1e6f : -kInf;
    reference.at(p, 2) = (p % 2) ? 5e4f : kInf;  // also larger than every masked value
  }
  MetricValues garbage = compute_metrics(test, reference, s.mask, kPerFrame);
  for (const std::string& name : kPerFrame) EXPECT_EQ(garbage.values.at(name), clean.values.at(name)) << name;

  // A NaN and an infinite pixel inside the disc count as if they were outside it.
  const size_t a = 12 * SsimCase::kSize + 12, b = 8 * SsimCase::kSize + 14;
  ASSERT_TRUE(s.mask[a] && s.mask[b]);
  test.at(a, 2) = kNaN;
  test.at(b, 0) = kInf;
  MetricValues with = compute_metrics(test, reference, s.mask, kPerFrame);
  std::vector<uint8_t> reduced = s.mask;
  reduced[a] = reduced[b] = 0;
  MetricValues without = compute_metrics(test, reference, reduced, kPerFrame);
  EXPECT_EQ(with.nonfinite_pixels, 2u);
  for (const std::string& name : kPerFrame) {
    if (name != "nonfinite_pixels") {
      EXPECT_DOUBLE_EQ(with.values.at(name), without.values.at(name)) << name;
    }
  }
}

TEST(Metrics, TemporalFlickerOfStaticAndFlickeringMethods) {
  // Pixel 0 is masked; pixel 1 is not and flickers wildly.
  std::vector<std::vector<uint8_t>> masks(3, {1, 0});
  std::vector<Image> reference(3, row_image({{2.0f, 2.0f, 2.0f}, {1.0f, 1.0f, 1.0f}}));

  // A static (even biased) method against a static reference: no flicker.
  std::vector<Image> biased(3, row_image({{2.5f, 1.0f, 2.0f}, {0.0f, 0.0f, 0.0f}}));
  biased[1].at(1, 0) = 50.0f;
  EXPECT_EQ(temporal_flicker(biased, reference, masks).value, 0.0);

  // Frame 1 brightens by (0.6, 0.3, 0), frame 2 goes back: each pair's mean |change| is 0.3; the
  // reference's masked mean over all frames is 2, so the flicker is 0.15.
  std::vector<Image> flicker = biased;
  for (Image& frame : flicker) frame.set_rgb(0, Color(2.0f, 2.0f, 2.0f));
  flicker[1].set_rgb(0, Color(2.6f, 2.3f, 2.0f));
  EXPECT_NEAR(*temporal_flicker(flicker, reference, masks).value, 0.15, 1e-6);
}

TEST(Metrics, TemporalFlickerComparesChangesWithTheReference) {
  std::vector<std::vector<uint8_t>> masks(3, {1});
  std::vector<Image> reference = {row_image({{1.0f, 1.0f, 1.0f}}), row_image({{2.0f, 2.0f, 2.0f}}),
                                  row_image({{3.0f, 3.0f, 3.0f}})};
  // Following the reference with a constant bias: zero.
  std::vector<Image> follows = reference;
  for (Image& frame : follows)
    for (float& v : frame.values()) v += 0.5f;
  EXPECT_NEAR(*temporal_flicker(follows, reference, masks).value, 0.0, 1e-7);

  // Lagging: changes (0, 2) against the reference's (1, 1): |-1| and |1|, mean 1, over mean 2 = 0.5.
  std::vector<Image> lags = {row_image({{1.0f, 1.0f, 1.0f}}), row_image({{1.0f, 1.0f, 1.0f}}),
                             row_image({{3.0f, 3.0f, 3.0f}})};
  EXPECT_NEAR(*temporal_flicker(lags, reference, masks).value, 0.5, 1e-7);

  // Scale free.
  for (auto* frames : {&lags, &reference})
    for (Image& frame : *frames)
      for (float& v : frame.values()) v *= 100.0f;
  EXPECT_NEAR(*temporal_flicker(lags, reference, masks).value, 0.5, 1e-6);

  // A pixel masked in only one frame of a pair does not count for that pair.
  std::vector<Image> two_test = {row_image({{1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f}}),
                                 row_image({{2.0f, 2.0f, 2.0f}, {9.0f, 9.0f, 9.0f}})};
  std::vector<Image> two_reference = {row_image({{1.0f, 1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}}),
                                      row_image({{1.0f, 1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}})};
  // Pair 1: only pixel 0, |1 - 0| = 1. Reference mean over the 3 masked (frame, pixel) entries = 1.
  EXPECT_NEAR(*temporal_flicker(two_test, two_reference, {{1, 0}, {1, 1}}).value, 1.0, 1e-7);

  // Fewer than two frames: undefined.
  MetricValue single = temporal_flicker({reference[0]}, {reference[0]}, {masks[0]});
  EXPECT_FALSE(single.value.has_value());
  EXPECT_EQ(single.undefined_reason, "flicker needs at least two frames");
  EXPECT_THROW(temporal_flicker(lags, reference, {masks[0]}), std::invalid_argument);
}

TEST(Metrics, RegistryDirectionsAndComparison) {
  const MetricInfo& psnr = find_metric("psnr");
  const MetricInfo& ssim = find_metric("ssim");
  const MetricInfo& rmse = find_metric("rmse");
  const MetricInfo& energy = find_metric("energy_ratio");
  EXPECT_TRUE(psnr.higher_is_better);
  EXPECT_TRUE(ssim.higher_is_better);
  EXPECT_FALSE(rmse.higher_is_better);
  EXPECT_FALSE(rmse.target.has_value());
  ASSERT_TRUE(energy.target.has_value());
  EXPECT_EQ(*energy.target, 1.0);
  EXPECT_EQ(psnr.unit, "dB");
  EXPECT_EQ(find_metric("mse").unit, "(W/m^2)^2");
  EXPECT_EQ(rmse.unit, "W/m^2");

  EXPECT_TRUE(metric_better(energy, 1.02, 0.9));
  EXPECT_FALSE(metric_better(energy, 0.9, 1.02));
  EXPECT_TRUE(metric_better(energy, 0.97, 1.05));
  EXPECT_TRUE(metric_better(psnr, 30.0, 20.0));
  EXPECT_TRUE(metric_better(psnr, std::numeric_limits<double>::infinity(), 80.0));
  EXPECT_TRUE(metric_better(rmse, 0.1, 0.2));
  EXPECT_FALSE(metric_better(rmse, 0.2, 0.2));
  EXPECT_TRUE(metric_better(rmse, 5.0, std::nan("")));
  EXPECT_FALSE(metric_better(rmse, std::nan(""), 5.0));

  std::vector<std::string> names;
  for (const MetricInfo& metric : metric_registry()) {
    names.push_back(metric.name);
    EXPECT_FALSE(metric.definition.empty()) << metric.name;
    EXPECT_EQ(metric.per_frame, metric.name != "temporal_flicker") << metric.name;
    EXPECT_EQ(metric.target.has_value(), metric.name == "energy_ratio") << metric.name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"mse", "rmse", "psnr", "ssim", "relmse", "energy_ratio", "max_error",
                                             "flip", "temporal_flicker", "nonfinite_pixels"}));
}

TEST(Metrics, UnknownNamesSuggestTheClosest) {
  try {
    find_metric("rmes");
    FAIL() << "no exception";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("did you mean 'rmse'"), std::string::npos) << error.what();
  }
  try {
    find_metric("energy-ratio");
    FAIL() << "no exception";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("did you mean 'energy_ratio'"), std::string::npos) << error.what();
  }
  SmallCase s;
  EXPECT_THROW(compute_metrics(s.test, s.reference, s.mask, {"psnr", "ssmi"}), InputError);
  EXPECT_THROW(compute_metrics(s.test, s.reference, s.mask, {"temporal_flicker"}), InputError);
}

TEST(Metrics, InvalidInputsThrow) {
  SmallCase s;
  EXPECT_THROW(compute_metrics(s.test, s.reference, {1, 1, 1}, {"mse"}), std::invalid_argument);
  EXPECT_THROW(compute_metrics(row_image({{1.0f, 1.0f, 1.0f}}), s.reference, s.mask, {"mse"}),
               std::invalid_argument);
  s.reference.at(0, 1) = kNaN;  // a broken reference inside the mask is an error, not a silent skip
  EXPECT_THROW(compute_metrics(s.test, s.reference, s.mask, {"mse"}), std::invalid_argument);
}

}  // namespace
}  // namespace causticbench
