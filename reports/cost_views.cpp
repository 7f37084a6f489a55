// The equal-time, equal-error and break-even views (declared in cost_views.h).
#include "reports/cost_views.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace causticbench {

namespace {

bool usable(const CostPoint& point) {
  return std::isfinite(point.frame_ms) && std::isfinite(point.error) && std::isfinite(point.prepare_seconds);
}

// Error a is at least as good as b.
bool as_good(const ErrorBetter& better, double a, double b) { return !better(b, a); }

}  // namespace

std::vector<EqualTimeRow> equal_time_view(const std::vector<CostPoint>& points, const std::vector<std::string>& methods,
                                          const std::vector<double>& budgets_ms, const ErrorBetter& better) {
  std::vector<EqualTimeRow> rows;
  for (double budget : budgets_ms) {
    EqualTimeRow row{budget, {}};
    for (const std::string& method : methods) {
      BudgetAnswer answer{method, std::nullopt, std::nullopt};
      for (size_t i = 0; i < points.size(); ++i) {
        const CostPoint& point = points[i];
        if (point.method != method || !usable(point)) continue;
        if (!answer.fastest || point.frame_ms < points[*answer.fastest].frame_ms) answer.fastest = i;
        if (point.frame_ms > budget) continue;
        if (!answer.best || better(point.error, points[*answer.best].error) ||
            (!better(points[*answer.best].error, point.error) && point.frame_ms < points[*answer.best].frame_ms))
          answer.best = i;
      }
      if (answer.best) answer.fastest.reset();
      row.methods.push_back(answer);
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<EqualErrorRow> equal_error_view(const std::vector<CostPoint>& points, const std::vector<std::string>& methods,
                                            const std::vector<double>& targets, const ErrorBetter& better) {
  std::vector<EqualErrorRow> rows;
  for (double target : targets) {
    EqualErrorRow row{target, {}};
    for (const std::string& method : methods) {
      TargetAnswer answer{method, std::nullopt, std::nullopt};
      for (size_t i = 0; i < points.size(); ++i) {
        const CostPoint& point = points[i];
        if (point.method != method || !usable(point)) continue;
        if (!answer.closest || better(point.error, points[*answer.closest].error)) answer.closest = i;
        if (!as_good(better, point.error, target)) continue;
        if (!answer.fastest || point.frame_ms < points[*answer.fastest].frame_ms ||
            (point.frame_ms == points[*answer.fastest].frame_ms && better(point.error, points[*answer.fastest].error)))
          answer.fastest = i;
      }
      if (answer.fastest) answer.closest.reset();
      row.methods.push_back(answer);
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<double> default_error_targets(const std::vector<CostPoint>& points, const ErrorBetter& better) {
  std::vector<std::string> methods;
  for (const CostPoint& point : points)
    if (usable(point) && std::find(methods.begin(), methods.end(), point.method) == methods.end())
      methods.push_back(point.method);
  std::vector<double> targets;
  for (const std::string& method : methods) {
    std::optional<double> best;
    for (const CostPoint& point : points)
      if (point.method == method && usable(point) && (!best || better(point.error, *best))) best = point.error;
    if (best && std::find(targets.begin(), targets.end(), *best) == targets.end()) targets.push_back(*best);
  }
  // Loosest first: a target is looser than another when the other is better.
  std::sort(targets.begin(), targets.end(), [&](double a, double b) { return better(b, a); });
  return targets;
}

std::vector<BreakEven> break_even_view(const std::vector<CostPoint>& points, const std::vector<std::string>& methods,
                                       const ErrorBetter& better) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  std::vector<BreakEven> result;
  for (const std::string& first : methods) {
    for (const std::string& second : methods) {
      if (first == second) continue;
      std::optional<BreakEven> chosen;
      for (size_t a = 0; a < points.size(); ++a) {
        const CostPoint& pa = points[a];
        if (pa.method != first || !usable(pa)) continue;
        const double prepare_a = pa.prepare_seconds * 1000.0;
        double frames = 0.0;  // N*(a): the largest crossing over the competitors
        std::optional<size_t> binding;
        bool any = false;
        for (size_t b = 0; b < points.size() && frames < kNever; ++b) {
          const CostPoint& pb = points[b];
          if (pb.method != second || !usable(pb) || !as_good(better, pb.error, pa.error)) continue;
          any = true;
          const double prepare_b = pb.prepare_seconds * 1000.0;
          double crossing;
          if (pa.frame_ms < pb.frame_ms)
            crossing = std::max(0.0, (prepare_a - prepare_b) / (pb.frame_ms - pa.frame_ms));
          else
            crossing = prepare_a <= prepare_b && pa.frame_ms == pb.frame_ms ? 0.0 : kNever;
          if (!binding || crossing > frames) {
            frames = crossing;
            binding = b;
          }
        }
        if (!any || frames == kNever) continue;
        // Only a method that precomputes more "overtakes"; one that is cheaper from the start is
        // dominated territory, which the trade-off plots show.
        if (!(prepare_a > points[*binding].prepare_seconds * 1000.0)) continue;
        if (!chosen || frames < chosen->frames) chosen = BreakEven{a, *binding, std::ceil(frames)};
      }
      if (chosen) result.push_back(*chosen);
    }
  }
  return result;
}

}  // namespace causticbench
