// The verdict list of reports/claim_verdicts.h: names, badges and counts.
#include "reports/claim_verdicts.h"

#include <fmt/format.h>

#include <vector>

namespace causticbench {

namespace {

std::string joined(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : ", ") + part;
  return out;
}

}  // namespace

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::confirmed:
      return "confirmed";
    case Verdict::partly:
      return "partly";
    case Verdict::refuted:
      return "refuted";
    case Verdict::not_separated:
      return "not separated";
    case Verdict::not_measured:
      break;
  }
  return "not measured";
}

const char* verdict_badge(Verdict verdict) {
  // "not measured" has a space, which a class name cannot hold.
  if (verdict == Verdict::not_separated) return "unseparated";
  return verdict == Verdict::not_measured ? "unmeasured" : verdict_name(verdict);
}

Verdict verdict_of_separated_count(size_t holding, size_t failing, size_t total) {
  if (total == 0) return Verdict::not_measured;
  if (holding == total) return Verdict::confirmed;
  if (holding > 0) return Verdict::partly;
  return failing > 0 ? Verdict::refuted : Verdict::not_separated;
}

Verdict verdict_of_count(size_t holding, size_t total) {
  if (total == 0) return Verdict::not_measured;
  if (holding == total) return Verdict::confirmed;
  return holding == 0 ? Verdict::refuted : Verdict::partly;
}

std::string ClaimCounts::breakdown() const {
  std::vector<std::string> parts;
  for (Verdict verdict : kVerdicts)
    if (verdict != Verdict::not_separated || of(verdict)) parts.push_back(fmt::format("{} {}", of(verdict), verdict_name(verdict)));
  return joined(parts);
}

std::string ClaimCounts::sentence() const {
  std::vector<std::string> rest;
  for (Verdict verdict : kVerdicts)
    if (verdict != Verdict::confirmed && of(verdict)) rest.push_back(fmt::format("{} {}", of(verdict), verdict_name(verdict)));
  return fmt::format("{} of {} claim{} confirmed{}.", of(Verdict::confirmed), total, total == 1 ? "" : "s",
                     rest.empty() ? "" : " (" + joined(rest) + ")");
}

}  // namespace causticbench
