// The verdicts a checked claim can have (docs/reports.md, "Claims"), defined once: the checker
// (reports/claims.cpp), the report's writers, the study's summary and the command line all name and
// count them through this list, so that no page can call a verdict by another name.
#pragma once

#include <array>
#include <cstddef>
#include <string>

namespace causticbench {

enum class Verdict {
  confirmed,     // the claim holds for every pair or group it covers
  partly,        // it holds for some of them and not for others (the evidence says how many)
  refuted,       // it holds for none of them
  // Measured with several seeds, no pair it covers is told apart: every pair's 95 % intervals overlap
  // (metrics/confidence.h), whatever the means say.
  not_separated,
  not_measured,  // too few finished runs match to decide, or the claim is malformed
};

// Every verdict, in the order pages list them.
inline constexpr std::array<Verdict, 5> kVerdicts = {Verdict::confirmed, Verdict::partly, Verdict::refuted,
                                                     Verdict::not_separated, Verdict::not_measured};

// "confirmed", "partly", "refuted", "not measured": the word in every table, results.json and summary.json.
const char* verdict_name(Verdict verdict);
// The HTML badge's class (reports/templates/report.css): green, amber, red, grey.
const char* verdict_badge(Verdict verdict);

// The verdict of a claim over `total` pairs or groups of which `holding` hold; not measured when there
// are none.
Verdict verdict_of_count(size_t holding, size_t total);
// The same with intervals: of `total` pairs, `holding` hold and `failing` fail with their intervals apart;
// the others are not separated. Any separated pair that holds: confirmed or partly; none, but one that
// fails: refuted; none separated at all: not separated.
Verdict verdict_of_separated_count(size_t holding, size_t failing, size_t total);

// Claims counted by verdict.
struct ClaimCounts {
  size_t total = 0;
  std::array<size_t, kVerdicts.size()> by_verdict{};

  void add(Verdict verdict) {
    ++total;
    ++by_verdict[static_cast<size_t>(verdict)];
  }
  size_t of(Verdict verdict) const { return by_verdict[static_cast<size_t>(verdict)]; }
  // "3 confirmed, 1 partly, 2 refuted, 1 not measured": every verdict, zeros included, but "not
  // separated" only where some claim has it (it needs seeds, which most experiments do not ask for).
  std::string breakdown() const;
  // "3 of 7 claims confirmed (1 partly, 2 refuted, 1 not measured).": the verdicts other than
  // confirmed only when some claim has them.
  std::string sentence() const;
};

}  // namespace causticbench
