// Pareto fronts: the public pareto_front() (reports/report.h) and the fronts of the report, of the
// primary metric against frame time and of each trade-off the experiment names, computed within each
// scene variant over all methods and per method (docs/reports.md, "Pareto fronts").
#include "reports/report.h"

#include <algorithm>
#include <cmath>

#include "reports/report_parts.h"

namespace causticbench {

std::vector<size_t> pareto_front(const std::vector<TradeoffPoint>& points,
                                 const std::function<bool(double, double)>& better_value) {
  return pareto_front(points, [](double a, double b) { return a < b; }, better_value);
}

std::vector<size_t> pareto_front(const std::vector<TradeoffPoint>& points,
                                 const std::function<bool(double, double)>& better_time,
                                 const std::function<bool(double, double)>& better_value) {
  std::vector<size_t> front;
  auto usable = [&](size_t i) { return std::isfinite(points[i].time) && std::isfinite(points[i].value); };
  for (size_t i = 0; i < points.size(); ++i) {
    if (!usable(i)) continue;
    bool dominated = false;
    for (size_t j = 0; j < points.size() && !dominated; ++j) {
      if (j == i || !usable(j)) continue;
      bool as_fast = !better_time(points[i].time, points[j].time);
      bool as_good = !better_value(points[i].value, points[j].value);
      bool strictly = better_time(points[j].time, points[i].time) || better_value(points[j].value, points[i].value);
      dominated = as_fast && as_good && strictly;
    }
    if (!dominated) front.push_back(i);
  }
  std::stable_sort(front.begin(), front.end(), [&](size_t a, size_t b) {
    if (points[a].time != points[b].time) return better_time(points[a].time, points[b].time);
    return better_value(points[a].value, points[b].value);
  });
  return front;
}

namespace report_detail {

namespace {

// The fronts of y against x within each variant, over all methods and per method.
std::vector<Fronts> fronts_of(const Report& report, const std::string& x, const std::string& y) {
  std::vector<Fronts> all(report.variants.size());
  // Looked up once: the fronts compare every pair of runs.
  QuantityInfo cost;  // an unregistered name counts as a cost, lower is better
  const QuantityInfo qx = find_quantity(x).value_or(cost), qy = find_quantity(y).value_or(cost);
  auto better_x = [&](double a, double b) { return quantity_better(qx, a, b); };
  auto better_y = [&](double a, double b) { return quantity_better(qy, a, b); };
  for (size_t v = 0; v < report.variants.size(); ++v) {
    Fronts& fronts = all[v];
    std::vector<size_t> candidates;
    std::vector<TradeoffPoint> points;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].variant_index != v) continue;
      auto first = report.runs[i].quantity(x);
      auto second = report.runs[i].quantity(y);
      if (!finite(first) || !finite(second)) continue;
      candidates.push_back(i);
      points.push_back({*first, *second});
    }
    for (size_t f : pareto_front(points, better_x, better_y)) fronts.overall.push_back(candidates[f]);
    for (const std::string& entry : report.entries) {
      std::vector<size_t> mine;
      std::vector<TradeoffPoint> my_points;
      for (size_t c = 0; c < candidates.size(); ++c) {
        if (report.runs[candidates[c]].entry != entry) continue;
        mine.push_back(candidates[c]);
        my_points.push_back(points[c]);
      }
      if (mine.empty()) continue;
      for (size_t f : pareto_front(my_points, better_x, better_y)) fronts.per_method[entry].push_back(mine[f]);
    }
  }
  return all;
}

}  // namespace

void compute_fronts(Report& report) {
  report.fronts = fronts_of(report, "frame_ms", report.primary);
  for (Tradeoff& tradeoff : report.tradeoffs) tradeoff.fronts = fronts_of(report, tradeoff.x, tradeoff.y);
}

}  // namespace report_detail

}  // namespace causticbench
