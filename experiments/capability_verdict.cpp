// The capability verdict rule (declared in capability_verdict.h).
#include "experiments/capability_verdict.h"

#include <cmath>

#include <fmt/format.h>

namespace causticbench {

const char* capability_verdict_name(CapabilityVerdict verdict) {
  switch (verdict) {
    case CapabilityVerdict::holds: return "holds";
    case CapabilityVerdict::refused: return "refused";
    case CapabilityVerdict::wrong: return "wrong";
    case CapabilityVerdict::neither: return "neither";
  }
  return "?";
}

CapabilityVerdict judge_capability(bool refused, std::optional<double> energy_ratio, std::optional<double> relmse) {
  if (refused) return CapabilityVerdict::refused;
  const double ratio = energy_ratio.value_or(NAN), error = relmse.value_or(NAN);
  if (!std::isfinite(ratio) || !std::isfinite(error)) return CapabilityVerdict::wrong;
  const double deviation = std::abs(ratio - 1.0);
  if (deviation <= kCapabilityEnergyTolerance && error <= kCapabilityRelMseBound) return CapabilityVerdict::holds;
  if (deviation > kCapabilityWrongMargin * kCapabilityEnergyTolerance ||
      error > kCapabilityWrongMargin * kCapabilityRelMseBound)
    return CapabilityVerdict::wrong;
  return CapabilityVerdict::neither;
}

bool capability_verdict_agrees(bool declared, CapabilityVerdict verdict) {
  if (declared) return verdict == CapabilityVerdict::holds;
  return verdict == CapabilityVerdict::refused || verdict == CapabilityVerdict::wrong;
}

std::string capability_rule_text() {
  return fmt::format("holds: |energy ratio - 1| <= {} and relMSE <= {}; wrong: |energy ratio - 1| > {} or relMSE > {} "
                     "(or not finite); refused: the method declined the scene",
                     kCapabilityEnergyTolerance, kCapabilityRelMseBound,
                     kCapabilityWrongMargin * kCapabilityEnergyTolerance, kCapabilityWrongMargin * kCapabilityRelMseBound);
}

}  // namespace causticbench
