// Pareto fronts of the error-versus-time plane: the public pareto_front() (reports/report.h) and the
// fronts of the report, computed within each scene variant over all methods and per method
// (docs/reports.md, "Pareto fronts").
#include "reports/report.h"

#include <algorithm>
#include <cmath>

#include "reports/report_parts.h"

namespace causticbench {

std::vector<size_t> pareto_front(const std::vector<TradeoffPoint>& points,
                                 const std::function<bool(double, double)>& better_value) {
  std::vector<size_t> front;
  auto usable = [&](size_t i) { return std::isfinite(points[i].time) && std::isfinite(points[i].value); };
  for (size_t i = 0; i < points.size(); ++i) {
    if (!usable(i)) continue;
    bool dominated = false;
    for (size_t j = 0; j < points.size() && !dominated; ++j) {
      if (j == i || !usable(j)) continue;
      bool as_fast = points[j].time <= points[i].time;
      bool as_good = !better_value(points[i].value, points[j].value);
      bool strictly = points[j].time < points[i].time || better_value(points[j].value, points[i].value);
      dominated = as_fast && as_good && strictly;
    }
    if (!dominated) front.push_back(i);
  }
  std::stable_sort(front.begin(), front.end(), [&](size_t a, size_t b) {
    if (points[a].time != points[b].time) return points[a].time < points[b].time;
    return better_value(points[a].value, points[b].value);
  });
  return front;
}

namespace report_detail {

void compute_fronts(Report& report) {
  report.fronts.assign(report.variants.size(), Fronts{});
  auto is_better = [&](double a, double b) { return better(report.primary, a, b); };
  for (size_t v = 0; v < report.variants.size(); ++v) {
    Fronts& fronts = report.fronts[v];
    std::vector<size_t> candidates;
    std::vector<TradeoffPoint> points;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].variant_index != v) continue;
      auto time = report.runs[i].frame_ms();
      auto value = report.runs[i].metric(report.primary);
      if (!finite(time) || !finite(value)) continue;
      candidates.push_back(i);
      points.push_back({*time, *value});
    }
    for (size_t f : pareto_front(points, is_better)) fronts.overall.push_back(candidates[f]);
    for (const std::string& method : report.methods) {
      std::vector<size_t> mine;
      std::vector<TradeoffPoint> my_points;
      for (size_t c = 0; c < candidates.size(); ++c) {
        if (report.runs[candidates[c]].method != method) continue;
        mine.push_back(candidates[c]);
        my_points.push_back(points[c]);
      }
      if (mine.empty()) continue;
      for (size_t f : pareto_front(my_points, is_better)) fronts.per_method[method].push_back(mine[f]);
    }
  }
}

}  // namespace report_detail

}  // namespace causticbench
