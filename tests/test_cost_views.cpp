// The quantity registry (every quantity has a direction; unknown names get the closest) and the cost views
// (equal time, equal error, total cost and break-even) on synthetic points: split from test_report_views.cpp,
// which keeps the run record and the report's views on a synthetic results folder.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "methods/quantity_registry.h"
#include "metrics/metrics.h"
#include "reports/cost_views.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

TEST(QuantityRegistry, EveryMetricTimingSizeAndCounterHasADirection) {
  const std::vector<QuantityInfo> all = quantity_registry();
  std::set<std::string> names;
  for (const QuantityInfo& quantity : all) {
    EXPECT_TRUE(names.insert(quantity.name).second) << quantity.name << " twice";
    EXPECT_FALSE(quantity.definition.empty()) << quantity.name;
    if (quantity.name != "receiver_pixels")
      EXPECT_NE(quantity.direction, QuantityDirection::none) << quantity.name;
    if (quantity.kind == QuantityKind::timing || quantity.kind == QuantityKind::size)
      EXPECT_FALSE(quantity.unit.empty()) << quantity.name;
  }
  for (const MetricInfo& metric : metric_registry()) EXPECT_TRUE(names.count(metric.name)) << metric.name;
  for (const char* name : {"frame_ms", "render_ms", "update_ms", "prepare_seconds", "memory_bytes", "peak_rss_bytes"})
    EXPECT_TRUE(names.count(name)) << name;
  for (const MethodEntry& entry : method_registry())
    for (const QuantityInfo& counter : entry.info().counters) EXPECT_TRUE(names.count(counter.name)) << counter.name;
  // Directions as the metrics define them.
  EXPECT_TRUE(quantity_better("psnr", 30.0, 20.0));
  EXPECT_TRUE(quantity_better("relmse", 0.1, 0.2));
  EXPECT_TRUE(quantity_better("energy_ratio", 0.95, 1.1));
  EXPECT_TRUE(quantity_better("frame_ms", 3.0, 4.0));
  EXPECT_FALSE(quantity_better("receiver_pixels", 3.0, 4.0)) << "no direction: never better";
}

TEST(QuantityRegistry, UnknownNamesGetTheClosest) {
  std::string message = causticbench::testing::input_error_message(
      [] { require_quantity("frame_msec", "claims[0].metric"); });
  EXPECT_NE(message.find("did you mean 'frame_ms'"), std::string::npos) << message;
  message = causticbench::testing::input_error_message([] { require_quantity("receiver_pixels", "tradeoffs[0]"); });
  EXPECT_NE(message.find("better one way"), std::string::npos) << message;
  EXPECT_NO_THROW(require_quantity("receiver_pixels", "claims[0].x", false));
}

// Error is relmse-like (lower is better) unless stated.
const ErrorBetter kLower = [](double a, double b) { return !std::isnan(a) && (std::isnan(b) || a < b); };

std::vector<CostPoint> synthetic_points() {
  return {{"A", 5, 0, 0.1},    {"A", 12, 0, 0.02}, {"A", 40, 0, 0.005}, {"B", 8, 0, 0.03},
          {"B", 30, 0, 0.04},  {"C", 200, 0, 0.001}, {"C", 1, 0, std::nan("")}};
}

TEST(CostViews, EqualTimeGivesTheBestErrorWithinEachBudget) {
  auto rows = equal_time_view(synthetic_points(), {"A", "B", "C"}, {10, 35, 100}, kLower);
  ASSERT_EQ(rows.size(), 3u);
  auto best = [&](size_t row, size_t method) { return rows[row].methods[method].best; };
  EXPECT_EQ(best(0, 0), 0u);
  EXPECT_EQ(best(0, 1), 3u);
  EXPECT_EQ(best(1, 0), 1u);
  EXPECT_EQ(best(1, 1), 3u) << "30 ms is within 35 but worse than 8 ms";
  EXPECT_EQ(best(2, 0), 2u);
  for (size_t row = 0; row < 3; ++row) {
    EXPECT_FALSE(best(row, 2)) << "C is never within 100 ms (its 1 ms point has no error)";
    EXPECT_EQ(rows[row].methods[2].fastest, 5u) << "not reached: says how fast C gets";
    EXPECT_FALSE(rows[row].methods[0].fastest);
  }
}

TEST(CostViews, EqualErrorGivesTheLeastTimeToReachEachTarget) {
  auto rows = equal_error_view(synthetic_points(), {"A", "B", "C"}, {0.05, 0.01}, kLower);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].methods[0].fastest, 1u) << "A's 5 ms run (0.1) does not reach 0.05";
  EXPECT_EQ(rows[0].methods[1].fastest, 3u);
  EXPECT_EQ(rows[0].methods[2].fastest, 5u);
  EXPECT_EQ(rows[1].methods[0].fastest, 2u);
  EXPECT_FALSE(rows[1].methods[1].fastest) << "B never reaches 0.01";
  EXPECT_EQ(rows[1].methods[1].closest, 3u) << "its best is 0.03";
  // A higher-is-better metric: a target is reached from above.
  const ErrorBetter higher = [](double a, double b) { return a > b; };
  std::vector<CostPoint> psnr = {{"A", 5, 0, 20}, {"A", 9, 0, 30}, {"B", 2, 0, 25}};
  auto above = equal_error_view(psnr, {"A", "B"}, {24}, higher);
  EXPECT_EQ(above[0].methods[0].fastest, 1u);
  EXPECT_EQ(above[0].methods[1].fastest, 2u);
  EXPECT_EQ(default_error_targets(synthetic_points(), kLower), (std::vector<double>{0.03, 0.005, 0.001}));
  EXPECT_EQ(default_error_targets(psnr, higher), (std::vector<double>{25, 30}));
}

TEST(CostViews, PrecomputingMethodOvertakesWhereTheTotalCostsCross) {
  // P precomputes 10 s and renders in 1 ms; F precomputes nothing: 11 ms at the same error, 5 ms at a
  // worse one (not a competitor), 0.5 ms at a much worse one. 10000 ms / (11 - 1) ms = 1000 frames.
  std::vector<CostPoint> points = {{"P", 1, 10, 0.01}, {"F", 11, 0, 0.01}, {"F", 5, 0, 0.05}, {"F", 0.5, 0, 0.5}};
  std::vector<BreakEven> crossings = break_even_view(points, {"P", "F"}, kLower);
  ASSERT_EQ(crossings.size(), 1u) << "F precomputes nothing: it never 'overtakes'";
  EXPECT_EQ(crossings[0].precomputing, 0u);
  EXPECT_EQ(crossings[0].competitor, 1u);
  EXPECT_EQ(crossings[0].frames, 1000.0);
  const double frames = crossings[0].frames;
  EXPECT_DOUBLE_EQ(10.0 * 1000.0 + frames * 1.0, 0.0 + frames * 11.0) << "the totals are equal there";
  // A competitor as accurate and as fast per frame: never overtaken.
  points.push_back({"F", 1, 0, 0.005});
  EXPECT_TRUE(break_even_view(points, {"P", "F"}, kLower).empty());
}


}  // namespace
}  // namespace causticbench
