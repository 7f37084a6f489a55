#include "experiments/light_account.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "core/errors.h"
#include "methods/registry.h"

namespace causticbench {

std::optional<LightAccount> account_for_light(const nlohmann::json& reference_record, const Capabilities& capabilities,
                                              double energy_ratio, double lost_fraction) {
  if (!reference_record.is_object() || !reference_record.contains("path_classes")) return std::nullopt;
  const nlohmann::json in_view = reference_record["path_classes"].value("in_view", nlohmann::json());
  if (!in_view.is_object() || in_view.value("flux", 0.0) <= 0.0 || !in_view.contains("joint")) return std::nullopt;
  std::map<std::string, bool> declared;
  for (const auto& [name, value] : capabilities.entries()) declared[name] = value;
  LightAccount account;
  account.energy = energy_ratio;
  account.lost = std::isfinite(lost_fraction) ? lost_fraction : 0.0;
  std::map<std::string, double> needs;
  for (const auto& [pair, entry] : in_view["joint"].items()) {
    const double share = entry.value("share", 0.0);
    bool modelled = true;
    for (const nlohmann::json& capability : entry.value("capabilities", nlohmann::json::array())) {
      const std::string name = capability.get<std::string>();
      if (declared.count(name) && !declared[name]) {
        modelled = false;
        needs[name] += share;
      }
    }
    if (!modelled) account.model += share;
  }
  for (const auto& [name, share] : needs)
    if (share > 0.0) account.unmodelled.emplace_back(name, share);
  std::stable_sort(account.unmodelled.begin(), account.unmodelled.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  // The energy the declarations and the lost flux account for is an interval: from delivering none of the
  // light in the unmodelled classes to delivering all of it (a method that does not model a class may still
  // put out an approximation of its light: csl's cones on a mirror), less the lost flux either way. The
  // lost flux and the model share may name the same light (a method that cannot place the light it does
  // not model may count it lost): together they explain at most all of it.
  const double lost = std::clamp(account.lost, 0.0, 1.0);
  const double lowest = 1.0 - std::min(1.0, lost + account.model), highest = 1.0 - lost;
  account.unexplained = account.energy < lowest    ? lowest - account.energy
                        : account.energy > highest ? highest - account.energy
                                                   : 0.0;
  account.flagged = std::abs(account.unexplained) > kUnexplainedLightTolerance;
  return account;
}

std::optional<LightAccount> account_for_record(const nlohmann::json& reference_record, const RunRecord& run) {
  const std::optional<double> energy = run.metric("energy_ratio");
  if (!energy || !std::isfinite(*energy) || run.empty_reference_frames) return std::nullopt;
  Capabilities capabilities;
  try {
    capabilities = find_method(run.method).info().capabilities;
  } catch (const std::exception&) {
    return std::nullopt;  // a method this build does not register: its declarations are unknown here
  }
  double lost = 0.0;
  if (run.lost_flux) {
    size_t frames = 0;
    double sum = 0.0;
    for (double fraction : run.lost_flux->frames)
      if (std::isfinite(fraction)) sum += fraction, ++frames;
    lost = frames ? sum / static_cast<double>(frames) : run.lost_flux->worst.fraction;
  }
  return account_for_light(reference_record, capabilities, *energy, lost);
}

std::string unmodelled_text(const LightAccount& account) {
  std::vector<std::string> needs;
  for (const auto& [name, share] : account.unmodelled) needs.push_back(fmt::format("{} {:.1f} %", name, 100.0 * share));
  return join(needs, ", ");
}

std::string describe_light_account(const LightAccount& account) {
  std::vector<std::string> parts;
  if (account.model >= 0.0005)
    parts.push_back(fmt::format("does not model {:.1f} % of this scene's caustic in view ({})", 100.0 * account.model,
                                unmodelled_text(account)));
  if (account.lost >= 0.0005) parts.push_back(fmt::format("loses {:.1f} % by its knobs", 100.0 * account.lost));
  if (account.flagged)
    parts.push_back(fmt::format("unexplained: {:.2f} of the light {}, not a declared limit", std::abs(account.unexplained),
                                account.unexplained > 0.0 ? "missing" : "in excess"));
  return join(parts, "; ") + fmt::format(" (energy {:.3f}, lost {:.3f}, model {:.3f}, unexplained {:+.3f})", account.energy,
                            account.lost, account.model, account.unexplained);
}

}  // namespace causticbench
