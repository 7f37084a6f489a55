// The trivial baselines (metrics/baselines.h): the black image scores what each metric's definition
// gives for a zero image (docs/metrics.md), the blurred reference is a normalised convolution, and the
// report shows both and flags the runs that do not beat the black image.
#include <cmath>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "metrics/baselines.h"
#include "reports/summary_model.h"
#include "tests/report_test_support.h"

using namespace causticbench;

namespace {

// A reference with structure and a mask that leaves out a band: 48 x 32, values 0.01 to about 5.
Image structured_reference(std::vector<uint8_t>& mask) {
  Image image(48, 32, 3);
  mask.assign(image.pixel_count(), 1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      const size_t pixel = static_cast<size_t>(y) * 48 + x;
      for (int c = 0; c < 3; ++c)
        image.at(pixel, c) = static_cast<float>(0.01 + (1.0 + c) * std::exp(-((x - 20.0) * (x - 20.0) + (y - 14.0) * (y - 14.0)) / 30.0));
      if (x > 40) mask[pixel] = 0;
    }
  return image;
}

}  // namespace

// mse = mean R^2, rmse its root, psnr = 10 log10(peak^2 / mse), relmse = mean R^2 / (R^2 + (0.1 mean R)^2),
// energy_ratio 0, max_error = the largest R: over the mask, every channel, to rounding.
TEST(Baselines, TheBlackImageScoresWhatEachDefinitionGivesForZero) {
  std::vector<uint8_t> mask;
  const Image reference = structured_reference(mask);
  double sum = 0.0, squares = 0.0, peak = 0.0, count = 0.0;
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel)
    if (mask[pixel])
      for (int c = 0; c < 3; ++c) {
        const double r = reference.at(pixel, c);
        sum += r;
        squares += r * r;
        peak = std::max(peak, r);
        count += 1.0;
      }
  const double mean = sum / count, epsilon = (0.1 * mean) * (0.1 * mean);
  double relative = 0.0;
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel)
    if (mask[pixel])
      for (int c = 0; c < 3; ++c) relative += reference.at(pixel, c) * reference.at(pixel, c) /
                                              (reference.at(pixel, c) * reference.at(pixel, c) + epsilon);
  const std::vector<BaselineScores> scores =
      score_baselines({reference}, {mask}, {"mse", "rmse", "psnr", "relmse", "energy_ratio", "max_error", "flip"});
  ASSERT_EQ(scores.size(), 2u);
  const BaselineScores& black = scores[0];
  EXPECT_EQ(black.name, "black image");
  EXPECT_NEAR(black.values.at("mse"), squares / count, 1e-9 * squares / count);
  EXPECT_NEAR(black.values.at("rmse"), std::sqrt(squares / count), 1e-9);
  EXPECT_NEAR(black.values.at("psnr"), 10.0 * std::log10(peak * peak / (squares / count)), 1e-9);
  EXPECT_NEAR(black.values.at("relmse"), relative / count, 1e-9);
  EXPECT_EQ(black.values.at("energy_ratio"), 0.0);
  EXPECT_NEAR(black.values.at("max_error"), peak, 1e-6);
  EXPECT_GT(black.values.at("flip"), 0.0);
  // The blurred reference keeps the energy roughly and scores better than black on every error here.
  const BaselineScores& blurred = scores[1];
  EXPECT_LT(blurred.values.at("relmse"), black.values.at("relmse"));
  EXPECT_NEAR(blurred.values.at("energy_ratio"), 1.0, 0.1);
}

// A normalised convolution: a constant over the mask stays that constant everywhere in the mask (no light
// leaks in from outside it, none is lost at its edges), and the outside stays zero.
TEST(Baselines, TheBlurredReferenceIsANormalisedConvolutionOverTheMask) {
  std::vector<uint8_t> mask;
  Image reference = structured_reference(mask);
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel)
    for (int c = 0; c < 3; ++c) reference.at(pixel, c) = mask[pixel] ? 2.5f : 100.0f;
  const Image blurred = blurred_baseline(reference, mask, baseline_blur_sigma(48, 32));
  EXPECT_EQ(baseline_blur_sigma(48, 32), 2.0);
  EXPECT_EQ(baseline_blur_sigma(640, 480), 20.0);
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel)
    for (int c = 0; c < 3; ++c) {
      if (mask[pixel]) EXPECT_NEAR(blurred.at(pixel, c), 2.5f, 1e-5f) << pixel;
      else EXPECT_EQ(blurred.at(pixel, c), 0.0f) << pixel;
    }
}

namespace causticbench::report_testing {

// The report's table holds both baselines' rows; a run whose primary metric is no better than the black
// image's is labelled so, and the findings say who does not beat it.
TEST_F(ReportTest, BaselinesAreRowsAndARunNoBetterThanBlackIsFlagged) {
  write_report(folder.string());
  std::string md = read_text(folder / "report.md");
  EXPECT_NE(md.find("| baseline | black image |"), std::string::npos) << md;
  EXPECT_NE(md.find("| baseline | blurred reference |"), std::string::npos) << md;
  EXPECT_NE(md.find("every run beats it"), std::string::npos) << md;
  EXPECT_EQ(md.find("(no better than a black image)"), std::string::npos) << md;
  // One run made worse than black on relMSE (1.5, where black scores below 1 by its definition).
  json record = json::parse(read_text(folder / "runs" / "pin_400" / "record.json"));
  record["metrics"]["relmse"] = 1.5;
  record["frames"][0]["metrics"]["relmse"] = 1.5;
  write_json(folder / "runs" / "pin_400" / "record.json", record);
  write_report(folder.string());
  md = read_text(folder / "report.md");
  EXPECT_NE(md.find("(no better than a black image)"), std::string::npos) << md;
  EXPECT_NE(md.find("1 run does not beat it"), std::string::npos) << md;
}

}  // namespace causticbench::report_testing

// A study's budget winner must beat the black image by a tenth of its score (reports/summary_model.h),
// in the metric's own direction.
TEST(Baselines, AWinnerBeatsTheBlackImageByTheStatedMargin) {
  using causticbench::report_detail::beats_black_by_margin;
  EXPECT_FALSE(beats_black_by_margin("relmse", 0.95, 1.0));
  EXPECT_TRUE(beats_black_by_margin("relmse", 0.85, 1.0));
  EXPECT_FALSE(beats_black_by_margin("flip", 0.38, 0.395));  // the quickstart ring's lpi grid at 32, nearly black
  EXPECT_FALSE(beats_black_by_margin("psnr", 10.5, 10.0));
  EXPECT_TRUE(beats_black_by_margin("psnr", 11.5, 10.0));
  EXPECT_TRUE(beats_black_by_margin("energy_ratio", 0.95, 0.0));   // 0.05 from 1, black 1 from it
  EXPECT_FALSE(beats_black_by_margin("energy_ratio", 0.05, 0.0));  // 0.95 from 1: not a tenth closer
  EXPECT_FALSE(beats_black_by_margin("relmse", std::nan(""), 1.0));
}
