// What a frame budget buys and what an accuracy costs (docs/reports.md, "Equal time, equal error,
// break-even"): over one scene variant's runs, each a point of (method, frame time, prepare time, error),
//   equal time:  for each frame-time budget, the best error each method reaches within it;
//   equal error: for each error target, the least frame time each method needs to reach it;
//   break-even:  the frame count after which a method that precomputes more costs less in total
//                (prepare + N x frame time) than another method at equal or better error.
// Pure functions of the points, so that the tests give them synthetic runs with known answers.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace causticbench {

struct CostPoint {
  std::string method;  // the column it belongs to: the run's experiment entry (Run::entry)
  double frame_ms = 0.0;         // per-frame time (median)
  double prepare_seconds = 0.0;  // precomputation, paid once
  double error = 0.0;            // the compared metric; NaN: undefined (the point is left out)
  std::string of_method;         // the method the entry runs (the study's standings are per method)
};

// `better(a, b)`: error a is strictly better than error b (quantity_better of the metric).
using ErrorBetter = std::function<bool(double, double)>;

struct BudgetAnswer {
  std::string method;
  std::optional<size_t> best;     // the best error within the budget (ties: the faster); none: not reached
  std::optional<size_t> fastest;  // not reached: the method's fastest point, to say by how much
};

struct EqualTimeRow {
  double budget_ms = 0.0;
  std::vector<BudgetAnswer> methods;  // in the order of `methods`
};

// One row per budget; a method with no usable point has neither best nor fastest.
std::vector<EqualTimeRow> equal_time_view(const std::vector<CostPoint>& points, const std::vector<std::string>& methods,
                                          const std::vector<double>& budgets_ms, const ErrorBetter& better);

struct TargetAnswer {
  std::string method;
  std::optional<size_t> fastest;  // the least frame time at an error at least as good as the target
  std::optional<size_t> closest;  // not reached: the method's best error, to say how close it came
};

struct EqualErrorRow {
  double target = 0.0;
  std::vector<TargetAnswer> methods;
};

std::vector<EqualErrorRow> equal_error_view(const std::vector<CostPoint>& points, const std::vector<std::string>& methods,
                                            const std::vector<double>& targets, const ErrorBetter& better);

// Targets when the experiment names none: the best error each method reaches, loosest first, each once,
// so that the view answers "what does every other method need to match this one's best?".
std::vector<double> default_error_targets(const std::vector<CostPoint>& points, const ErrorBetter& better);

struct BreakEven {
  size_t precomputing = 0;  // the point of the method that precomputes more
  size_t competitor = 0;    // the other method's point that stays cheaper longest at equal or better error
  double frames = 0.0;      // from this many frames on the precomputing point costs no more (0: from the start)
};

// For every ordered pair of methods (A, B): A's point a and B's points at least as accurate as a; a
// overtakes B after N* = max over those b of (P_a - P_b) / (f_b - f_a) frames (P in ms), never when some
// such b is as fast per frame and precomputes no more. Reported per pair: the a with the smallest finite
// N*, when a precomputes more than the binding b (a method that precomputes nothing is never "A").
std::vector<BreakEven> break_even_view(const std::vector<CostPoint>& points, const std::vector<std::string>& methods,
                                       const ErrorBetter& better);

}  // namespace causticbench
