// What the report says of each checked claim: the evidence sentence (plain, Markdown or HTML) with the
// runs and numbers that decided the verdict, the claim's entry in results.json, and the count line of
// the summary. The verdicts themselves come from claims.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

std::string code_text(const std::string& text, Format format) {
  if (format == Format::markdown) {
    // A code span is literal (HTML in it is shown, not run) as long as its fence is longer than any run
    // of backticks inside: a user's backtick must not close it.
    size_t longest = 0, run = 0;
    for (char c : text) longest = std::max(longest, run = c == '`' ? run + 1 : 0);
    const std::string fence(longest + 1, '`');
    const bool pad = !text.empty() && (text.front() == '`' || text.back() == '`');
    return fence + (pad ? " " : "") + text + (pad ? " " : "") + fence;
  }
  if (format == Format::html) return "<code>" + html_escape(text) + "</code>";
  return text;
}

std::string escaped(const std::string& text, Format format) {
  return format == Format::html ? html_escape(text) : format == Format::markdown ? md_text(text) : text;
}

std::string runs_text(size_t count) { return fmt::format("{} run{}", count, count == 1 ? "" : "s"); }

// " (1 failed run and 2 runs with an undefined value not counted)", or "" when every matching run counted.
std::string not_counted_note(size_t failed, size_t undefined) {
  std::vector<std::string> parts;
  if (failed) parts.push_back(fmt::format("{} failed run{}", failed, failed == 1 ? "" : "s"));
  if (undefined) parts.push_back(fmt::format("{} with an undefined value", runs_text(undefined)));
  return parts.empty() ? "" : " (" + join(parts, " and ") + " not counted)";
}

json claim_point_json(const Report& report, const std::optional<ClaimPoint>& point) {
  if (!point) return nullptr;
  const Run& run = report.runs[point->run];
  json out = {{"key", run.key}, {"label", run.label}, {"value", point->value}};
  if (report.multi()) out["variant"] = run.variant;
  return out;
}

// The tolerance a `same` claim allows: "within 0.05 relative", "within 0.001", or both joined by "or".
std::string tolerance_text(const ClaimResult& result) {
  std::vector<std::string> parts;
  if (result.relative_tolerance > 0.0) parts.push_back(num(result.relative_tolerance) + " relative");
  if (result.absolute_tolerance > 0.0 || parts.empty()) parts.push_back(num(result.absolute_tolerance) + " absolute");
  return "within " + join(parts, " or ");
}

// A measured `same` claim: how many pairs lie within the tolerance, and the pair that decides the most.
template <typename Point>
std::string same_evidence(const ClaimResult& result, const std::string& run, const std::string& than,
                          const std::string& first_note, const std::string& other_note, const std::string& quantity,
                          const Point& point) {
  double a = result.first->value, b = result.other->value;
  double larger = std::max(std::abs(a), std::abs(b));
  std::string relative = larger > 0.0 ? fmt::format(" ({} relative)", num(std::abs(a - b) / larger)) : "";
  return fmt::format("{} matching {}{} against {} matching {}{}: {} of {} pair{} {} {}; {}: {} against {}, "
                     "difference {}{}.",
                     runs_text(result.first_count), run, first_note, runs_text(result.other_count), than, other_note,
                     result.pairs_holding, result.pairs, result.pairs == 1 ? "" : "s",
                     result.pairs == 1 ? "is" : "are", tolerance_text(result),
                     result.pairs_holding == result.pairs ? "nearest its edge" : "farthest beyond it", point(*result.first),
                     point(*result.other), quantity + " " + num(std::abs(a - b)), relative);
}

}  // namespace

// Why the claim has its verdict, with the numbers that decided it.
std::string claim_evidence(const Report& report, const ClaimResult& result, Format format) {
  if (!result.problem.empty()) return escaped(result.problem, format);
  const json& claim = result.claim;
  std::string quantity = escaped(result.quantity, format);
  auto point = [&](const ClaimPoint& p) {
    // With several seeds, the mean and its 95 % half-width.
    const std::optional<MetricInterval> interval = report.runs[p.run].interval(result.quantity);
    const std::string spread =
        report.seeds > 1 && interval ? " \u00b1 " + num(interval->half_width) : std::string();
    return escaped(report.display(p.run), format) + " (" + quantity + " " + num(p.value) + spread + ")";
  };
  const std::string apart =
      result.pairs_not_separated
          ? fmt::format(" {} of {} pair{} not separated: the 95 % intervals overlap.", result.pairs_not_separated,
                        std::max<size_t>(result.pairs, 1), std::max<size_t>(result.pairs, 1) == 1 ? "" : "s")
          : "";
  std::string direction = quantity + ": " + escaped(direction_text(result.quantity), format) + ".";
  const std::string first_note = not_counted_note(result.failed_first, result.undefined_first);
  const std::string other_note = not_counted_note(result.failed_other, result.undefined_other);
  if (result.kind == "best") {
    std::string among = code_text(string_member(claim, "among"), format);
    std::string expect = code_text(string_member(claim, "expect"), format);
    size_t total = result.first_count + result.other_count;
    if (result.verdict == Verdict::not_measured) {
      return fmt::format("{} with a {} value match{} {}{}, {} of them matching {}: the check needs at least 2, "
                         "one matching {} and one not.",
                         runs_text(total), quantity, total == 1 ? "es" : "", among, first_note,
                         result.first_count, expect, expect);
    }
    bool confirmed = quantity_better(result.quantity, result.first->value, result.other->value);
    const ClaimPoint& best = confirmed ? *result.first : *result.other;
    const ClaimPoint& runner = confirmed ? *result.other : *result.first;
    return fmt::format("best of {} matching {}{}: {}, which {} {}; best run {} it: {}.{} {}", runs_text(total), among,
                       first_note, point(best), confirmed ? "matches" : "does not match",
                       expect, confirmed ? "not matching" : "matching", point(runner), apart, direction);
  }
  if (result.kind == "better" || result.kind == "same") {
    std::string run = code_text(string_member(claim, "run"), format);
    std::string than = code_text(string_member(claim, "than"), format);
    if (result.verdict == Verdict::not_measured) {
      return fmt::format("{} with a {} value match{} {}{}, {} match{} {}{}: the check needs at least 1 on each side.",
                         runs_text(result.first_count), quantity, result.first_count == 1 ? "es" : "", run,
                         first_note, result.other_count, result.other_count == 1 ? "es" : "",
                         than, other_note);
    }
    if (result.kind == "same") return same_evidence(result, run, than, first_note, other_note, quantity, point);
    // With several pairs, how many of them beat: what makes the verdict partly.
    std::string pairs = result.pairs > 1 ? fmt::format(" Better in {} of {} pairs.", result.pairs_holding, result.pairs)
                                         : "";
    return fmt::format("worst of {} matching {}{}: {}; best of {} matching {}{}: {}.{}{} {}",
                       runs_text(result.first_count), run, first_note, point(*result.first),
                       runs_text(result.other_count), than, other_note, point(*result.other), pairs, apart,
                       direction);
  }
  if (result.kind == "ratio") {
    std::string run = code_text(string_member(claim, "run"), format);
    std::string than = code_text(string_member(claim, "than"), format);
    if (result.verdict == Verdict::not_measured) {
      std::string base =
          result.other ? fmt::format(" (the base {} is {}: no ratio)", quantity, num(result.other->value)) : "";
      return fmt::format("{} with a {} value match{} {}{}, {} match{} {}{}: the ratio needs exactly 1 on each side{}.",
                         runs_text(result.first_count), quantity, result.first_count == 1 ? "es" : "", run,
                         first_note, result.other_count, result.other_count == 1 ? "es" : "", than, other_note,
                         base);
    }
    return fmt::format("{} / {} = {}\u00d7 ({} {}).", point(*result.first), point(*result.other), num(result.ratio),
                       result.ratio <= result.at_most ? "\u2264" : ">", num(result.at_most));
  }
  std::string x = escaped(string_member(claim, "x"), format);
  std::string among = code_text(string_member(claim, "among"), format);
  std::string grouped = result.group_by.empty() ? "" : ", grouped by " + escaped(join(result.group_by, ", "), format);
  std::string text = fmt::format("{} against {} over {} matching {}{}{}", quantity, x, runs_text(result.points), among,
                                 first_note, grouped);
  if (result.verdict == Verdict::not_measured) {
    return text + fmt::format(": no {} has {} points with different {} values to fit.",
                              result.group_by.empty() ? "set" : "group", kLinearMinPoints, x);
  }
  std::vector<std::string> parts;
  size_t fitted = 0, passed = 0;
  for (const LinearGroup& group : result.groups) {
    fitted += group.fitted;
    passed += group.passed;
    std::string part = group.knobs.empty() ? "" : escaped(knobs_text(group.knobs), format) + ": ";
    if (!group.fitted) {
      part += fmt::format("{} point{}, not fitted", group.xs.size(), group.xs.size() == 1 ? "" : "s");
    } else {
      part += fmt::format("{} = {} \u00d7 {} {} {}, R\u00b2 {} {} {}, n = {}", quantity, num(group.slope), x,
                          group.intercept < 0 ? "\u2212" : "+", num(std::abs(group.intercept)), num(group.r2),
                          group.passed ? "\u2265" : "<", num(result.min_r2), group.xs.size());
    }
    parts.push_back(part);
  }
  // With several fitted groups, how many reach min_r2: what makes the verdict partly.
  std::string count = fitted > 1 ? fmt::format(" Linear in {} of {} fitted groups.", passed, fitted) : "";
  return text + ": " + join(parts, "; ") + "." + count;
}

// The claim as experiment.json states it, with "verdict", "evidence" (plain text) and "details".
json claim_json(const Report& report, const ClaimResult& result) {
  json out = result.claim.is_object() ? result.claim : json{{"claim", result.claim}};
  out["verdict"] = verdict_name(result.verdict);
  out["evidence"] = claim_evidence(report, result, Format::plain);
  json details = json::object();
  if (!result.problem.empty()) {
    details["problem"] = result.problem;
  } else if (result.kind == "best") {
    details = {{"direction", direction_text(result.quantity)},
               {"runs", result.first_count + result.other_count},
               {"matching_expect", result.first_count},
               {"failed_runs", result.failed_first},
               {"undefined_runs", result.undefined_first},
               {"best_matching_expect", claim_point_json(report, result.first)},
               {"best_not_matching_expect", claim_point_json(report, result.other)}};
    if (result.verdict != Verdict::not_measured)
      details["best"] = claim_point_json(report, result.verdict == Verdict::confirmed ? result.first : result.other);
  } else if (result.kind == "better") {
    details = {{"direction", direction_text(result.quantity)},
               {"run_runs", result.first_count},
               {"than_runs", result.other_count},
               {"failed_runs", result.failed_first + result.failed_other},
               {"undefined_runs", result.undefined_first + result.undefined_other},
               {"worst_of_run", claim_point_json(report, result.first)},
               {"best_of_than", claim_point_json(report, result.other)},
               {"pairs", result.pairs},
               {"pairs_better", result.pairs_holding}};
  } else if (result.kind == "same") {
    details = {{"run_runs", result.first_count},
               {"than_runs", result.other_count},
               {"failed_runs", result.failed_first + result.failed_other},
               {"undefined_runs", result.undefined_first + result.undefined_other},
               {"absolute_tolerance", result.absolute_tolerance},
               {"relative_tolerance", result.relative_tolerance},
               {"pairs", result.pairs},
               {"pairs_within", result.pairs_holding},
               {"deciding_run", claim_point_json(report, result.first)},
               {"deciding_than", claim_point_json(report, result.other)}};
  } else if (result.kind == "ratio") {
    details = {{"run_runs", result.first_count},
               {"than_runs", result.other_count},
               {"failed_runs", result.failed_first + result.failed_other},
               {"undefined_runs", result.undefined_first + result.undefined_other},
               {"run", claim_point_json(report, result.first)},
               {"than", claim_point_json(report, result.other)},
               {"ratio", std::isfinite(result.ratio) ? json(result.ratio) : json(nullptr)},
               {"at_most", result.at_most}};
  } else {
    json groups = json::array();
    const LinearGroup* only = nullptr;
    size_t fitted = 0;
    for (const LinearGroup& group : result.groups) {
      json keys = json::array();
      for (size_t i : group.runs) keys.push_back(report.runs[i].key);
      json entry = {{"knobs", group.knobs}, {"n", group.xs.size()}, {"runs", keys}, {"fitted", group.fitted}};
      if (group.fitted) {
        entry.update(
            {{"slope", group.slope}, {"intercept", group.intercept}, {"r2", group.r2}, {"passed", group.passed}});
        only = &group;
        ++fitted;
      }
      groups.push_back(entry);
    }
    details = {{"n", result.points}, {"failed_runs", result.failed_first}, {"undefined_runs", result.undefined_first},
               {"min_r2", result.min_r2},
               {"group_by", result.group_by}, {"groups", groups}};
    if (fitted == 1) details.update({{"slope", only->slope}, {"intercept", only->intercept}, {"r2", only->r2}});
  }
  out["details"] = details;
  return out;
}

// "3 of 4 claims confirmed (1 refuted).": the summary's line, empty without claims.
std::string claims_count_text(const Report& report) {
  if (report.claims.empty()) return "";
  return count_claims(report).sentence();
}

ClaimCounts count_claims(const Report& report) {
  ClaimCounts counts;
  for (const ClaimResult& result : report.claims) counts.add(result.verdict);
  return counts;
}

}  // namespace causticbench::report_detail
