// The claims of experiment.json checked on the stored runs (docs/reports.md, "Claims"): "best" (the
// best run matches a filter), "better" (every run of one filter beats every run of another), "same"
// (every run of one filter lies within a tolerance of every run of another), "linear" (a quantity
// grows linearly with a knob, per group of the other knobs) and "ratio" (one run's quantity over
// another's stays within a bound: filtered over unfiltered render time). A claim over several pairs or
// groups is "partly" confirmed when some hold and others do not (reports/claim_verdicts.h). Only the
// verdicts and the numbers behind them are computed here; claim_evidence.cpp puts them into words.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>

#include "experiments/experiment.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

// A claim's quantity of a run (methods/quantity_registry.h): a metric, timing (median), size or counter.
std::optional<double> claim_value(const Run& run, const std::string& name) {
  std::optional<double> value = run.quantity(name);
  return finite(value) ? value : std::nullopt;
}

std::optional<double> knob_number(const json& knobs, const std::string& name) {
  const json& value = member(knobs, name);
  if (value.is_number()) return value.get<double>();
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    try {
      size_t used = 0;
      double parsed = std::stod(text, &used);
      if (used == text.size()) return parsed;
    } catch (const std::exception&) {
    }
  }
  return std::nullopt;
}

// The ok runs matching `filter` that have a value of `quantity`, how many failed runs match it, and how
// many ok runs match it with an undefined value (docs/metrics.md, "Undefined values").
std::vector<ClaimPoint> claim_points(const Report& report, const std::string& filter, const std::string& quantity,
                                     size_t& failed, size_t& undefined) {
  std::vector<ClaimPoint> points;
  failed = 0;
  undefined = 0;
  for (size_t i = 0; i < report.runs.size(); ++i) {
    const Run& run = report.runs[i];
    if (!record_matches_filter(run.record, filter)) continue;
    if (!run.ok) {
      ++failed;
      continue;
    }
    if (auto value = claim_value(run, quantity))
      points.push_back({i, *value});
    else if (!run.undefined_reason(quantity).empty())
      ++undefined;
  }
  return points;
}

// The best point (first of equals), or the worst with `worst`.
std::optional<ClaimPoint> extreme(const std::vector<ClaimPoint>& points, const std::string& quantity, bool worst) {
  std::optional<ClaimPoint> found;
  for (const ClaimPoint& point : points) {
    if (!found || (worst ? quantity_better(quantity, found->value, point.value)
                         : quantity_better(quantity, point.value, found->value)))
      found = point;
  }
  return found;
}

// Least squares y = slope x + intercept; R^2 = 1 - SS_res / SS_tot (1 for an exact fit).
void fit_line(LinearGroup& group) {
  size_t n = group.xs.size();
  if (n < kLinearMinPoints) return;
  double mean_x = 0.0, mean_y = 0.0;
  for (size_t i = 0; i < n; ++i) {
    mean_x += group.xs[i];
    mean_y += group.ys[i];
  }
  mean_x /= static_cast<double>(n);
  mean_y /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double dx = group.xs[i] - mean_x, dy = group.ys[i] - mean_y;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (!(sxx > 0.0)) return;  // x does not vary: no line to fit
  group.fitted = true;
  group.slope = sxy / sxx;
  group.intercept = mean_y - group.slope * mean_x;
  double residual = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double e = group.ys[i] - (group.slope * group.xs[i] + group.intercept);
    residual += e * e;
  }
  group.r2 = syy > 0.0 ? 1.0 - residual / syy : 1.0;
}

void evaluate_best(const Report& report, ClaimResult& result) {
  std::string among = string_member(result.claim, "among"), expect = string_member(result.claim, "expect");
  std::vector<ClaimPoint> points =
      claim_points(report, among, result.quantity, result.failed_first, result.undefined_first);
  std::vector<ClaimPoint> expected, others;
  for (const ClaimPoint& point : points)
    (record_matches_filter(report.runs[point.run].record, expect) ? expected : others).push_back(point);
  result.first_count = expected.size();
  result.other_count = others.size();
  result.first = extreme(expected, result.quantity, false);
  result.other = extreme(others, result.quantity, false);
  if (points.size() < 2 || !result.first || !result.other) return;
  // One best run: it matches `expect` or it does not, so there is no "partly"; with intervals that overlap,
  // neither is told apart.
  result.verdict = quantity_better(result.quantity, result.first->value, result.other->value) ? Verdict::confirmed
                                                                                            : Verdict::refuted;
  if (!separated(report.runs[result.first->run], report.runs[result.other->run], result.quantity)) {
    result.verdict = Verdict::not_separated;
    result.pairs_not_separated = 1;
  }
}

// The values of the runs matching `run` and `than` (better, same, ratio), with their counts, failed and
// undefined runs recorded in the result.
std::pair<std::vector<ClaimPoint>, std::vector<ClaimPoint>> run_and_than_points(const Report& report,
                                                                                ClaimResult& result) {
  std::vector<ClaimPoint> mine =
      claim_points(report, string_member(result.claim, "run"), result.quantity, result.failed_first,
                   result.undefined_first);
  std::vector<ClaimPoint> theirs =
      claim_points(report, string_member(result.claim, "than"), result.quantity, result.failed_other,
                   result.undefined_other);
  result.first_count = mine.size();
  result.other_count = theirs.size();
  return {std::move(mine), std::move(theirs)};
}

void evaluate_better(const Report& report, ClaimResult& result) {
  const auto [mine, theirs] = run_and_than_points(report, result);
  result.first = extreme(mine, result.quantity, true);
  result.other = extreme(theirs, result.quantity, false);
  // Every pair counts: all beat (the worst of `run` beats the best of `than`), none, or some.
  // With intervals (several seeds), a pair whose intervals overlap is not separated, whichever mean is better.
  size_t holding_apart = 0, failing_apart = 0;
  for (const ClaimPoint& a : mine)
    for (const ClaimPoint& b : theirs) {
      ++result.pairs;
      const bool holds = quantity_better(result.quantity, a.value, b.value);
      result.pairs_holding += holds;
      if (!separated(report.runs[a.run], report.runs[b.run], result.quantity))
        ++result.pairs_not_separated;
      else
        ++(holds ? holding_apart : failing_apart);
    }
  result.verdict = result.pairs_not_separated ? verdict_of_separated_count(holding_apart, failing_apart, result.pairs)
                                              : verdict_of_count(result.pairs_holding, result.pairs);
}

// How far |a - b| lies beyond what the claim's tolerances allow for the pair (<= 0: within).
double excess_over_tolerance(const ClaimResult& result, double a, double b) {
  double allowed = std::max(result.absolute_tolerance,
                            result.relative_tolerance * std::max(std::abs(a), std::abs(b)));
  return std::abs(a - b) - allowed;
}

void evaluate_same(const Report& report, ClaimResult& result) {
  result.absolute_tolerance = number(result.claim, "absolute_tolerance").value_or(0.0);
  result.relative_tolerance = number(result.claim, "relative_tolerance").value_or(0.0);
  const auto [mine, theirs] = run_and_than_points(report, result);
  // The evidence names the pair that decides the most: the one farthest beyond its tolerance (when all
  // are within, the one nearest to its edge).
  std::optional<double> worst;
  for (const ClaimPoint& a : mine)
    for (const ClaimPoint& b : theirs) {
      double excess = excess_over_tolerance(result, a.value, b.value);
      ++result.pairs;
      result.pairs_holding += excess <= 0.0;
      if (!worst || excess > *worst) {
        worst = excess;
        result.first = a;
        result.other = b;
      }
    }
  result.verdict = verdict_of_count(result.pairs_holding, result.pairs);
}

void evaluate_linear(const Report& report, ClaimResult& result) {
  std::string x = string_member(result.claim, "x");
  result.min_r2 = number(result.claim, "min_r2").value_or(0.98);
  std::vector<size_t> runs;
  std::vector<json> knobs;
  std::vector<double> xs, ys;
  for (const ClaimPoint& point : claim_points(report, string_member(result.claim, "among"), result.quantity,
                                             result.failed_first, result.undefined_first)) {
    const Run& run = report.runs[point.run];
    json resolved = run_knobs(run);
    auto x_value = knob_number(resolved, x);
    if (!finite(x_value)) continue;
    resolved.erase(x);
    resolved["method"] = run.method;
    runs.push_back(point.run);
    knobs.push_back(std::move(resolved));
    xs.push_back(*x_value);
    ys.push_back(point.value);
  }
  result.points = runs.size();
  // Group by every other knob (and the method) whose value differs between the runs. receiver_pixels is
  // measured, not set, so it never groups; nor does the variant when x is receiver_pixels (the variants
  // are what makes x vary).
  std::set<std::string> names;
  for (const json& k : knobs)
    for (const auto& [name, value] : k.items()) names.insert(name);
  names.erase("receiver_pixels");
  if (x == "receiver_pixels") names.erase("variant");
  for (const std::string& name : names) {
    std::set<std::string> values;
    for (const json& k : knobs) values.insert(member(k, name).dump());
    if (values.size() > 1) result.group_by.push_back(name);
  }
  if (std::count(result.group_by.begin(), result.group_by.end(), "method")) {
    result.group_by.erase(std::find(result.group_by.begin(), result.group_by.end(), "method"));
    result.group_by.insert(result.group_by.begin(), "method");
  }
  for (size_t p = 0; p < runs.size(); ++p) {
    json key = json::object();
    for (const std::string& name : result.group_by) key[name] = member(knobs[p], name);
    auto group = std::find_if(result.groups.begin(), result.groups.end(),
                              [&](const LinearGroup& g) { return g.knobs == key; });
    if (group == result.groups.end()) {
      result.groups.push_back(LinearGroup{});
      group = std::prev(result.groups.end());
      group->knobs = key;
    }
    group->runs.push_back(runs[p]);
    group->xs.push_back(xs[p]);
    group->ys.push_back(ys[p]);
  }
  // Every fitted group counts: all pass, none, or some (partly: the line holds for some settings of the
  // other knobs and not for others).
  size_t fitted = 0, passed = 0;
  for (LinearGroup& group : result.groups) {
    fit_line(group);
    if (!group.fitted) continue;
    group.passed = group.r2 >= result.min_r2;
    ++fitted;
    passed += group.passed;
  }
  result.verdict = verdict_of_count(passed, fitted);
}

// The ratio is only stated for one run against one run: with several on a side, which pair the number
// describes would be a choice the reader cannot see, so the claim is not measured instead.
void evaluate_ratio(const Report& report, ClaimResult& result) {
  result.at_most = *number(result.claim, "at_most");  // checked finite by evaluate_claims
  const auto [mine, theirs] = run_and_than_points(report, result);
  if (mine.size() != 1 || theirs.size() != 1) return;
  result.first = mine.front();
  result.other = theirs.front();
  if (!(result.other->value > 0.0)) return;  // no ratio to a zero or negative base
  result.ratio = result.first->value / result.other->value;
  result.verdict = result.ratio <= result.at_most ? Verdict::confirmed : Verdict::refuted;
}

}  // namespace

void evaluate_claims(Report& report) {
  const json& claims = member(report.experiment, "claims");
  if (!claims.is_array()) return;
  for (const json& claim : claims) {
    ClaimResult result;
    result.claim = claim;
    result.kind = string_member(claim, "kind");
    result.verdict = Verdict::not_measured;
    std::vector<std::string> needed;
    if (result.kind == "best")
      needed = {"metric", "among", "expect"};
    else if (result.kind == "better" || result.kind == "same")
      needed = {"metric", "run", "than"};
    else if (result.kind == "linear")
      needed = {"x", "y", "among"};
    else if (result.kind == "ratio")
      needed = {"y", "run", "than"};
    else
      result.problem = "unknown kind '" + result.kind + "' (expected best, better, same, linear or ratio)";
    for (const std::string& field : needed)
      if (!member(claim, field).is_string() && result.problem.empty())
        result.problem = "the claim has no '" + field + "'";
    if (result.kind == "ratio" && result.problem.empty() && !finite(number(claim, "at_most")))
      result.problem = "the claim has no 'at_most' bound";
    // best, better and same name a `metric`; linear and ratio a `y`. Only best and better rank, so only
    // they need a quantity with a better direction (same compares values, as linear's y).
    const bool ranked = result.kind == "best" || result.kind == "better";
    result.quantity = string_member(claim, result.kind == "linear" || result.kind == "ratio" ? "y" : "metric");
    if (result.problem.empty() && !find_quantity(result.quantity))
      result.problem = "'" + result.quantity + "' is not " + expected_quantity_text(result.quantity, ranked);
    if (result.problem.empty()) {
      if (result.kind == "best")
        evaluate_best(report, result);
      else if (result.kind == "better")
        evaluate_better(report, result);
      else if (result.kind == "same")
        evaluate_same(report, result);
      else if (result.kind == "linear")
        evaluate_linear(report, result);
      else
        evaluate_ratio(report, result);
    }
    report.claims.push_back(std::move(result));
  }
}

}  // namespace causticbench::report_detail
