#include "experiments/light_account.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/path_classes.h"
#include "methods/registry.h"

namespace causticbench {

const nlohmann::json* reference_light_in_view(const nlohmann::json& reference_record) {
  if (!reference_record.is_object() || !reference_record.contains("path_classes")) return nullptr;
  const nlohmann::json& classes = reference_record["path_classes"];
  if (!classes.is_object() || !classes.contains("in_view") || !classes["in_view"].is_object()) return nullptr;
  const nlohmann::json& in_view = classes["in_view"];
  const double amount = in_view.contains("pixel_sum") ? in_view.value("pixel_sum", 0.0) : in_view.value("flux", 0.0);
  return amount > 0.0 ? &in_view : nullptr;
}

std::optional<LightAccount> account_for_light(const nlohmann::json& reference_record, const Capabilities& capabilities,
                                              double energy_ratio, double lost_fraction, double moved) {
  const nlohmann::json* found = reference_light_in_view(reference_record);
  if (!found || !found->contains("joint")) return std::nullopt;
  const nlohmann::json& in_view = *found;
  std::map<std::string, bool> declared;
  for (const auto& [name, value] : capabilities.entries()) declared[name] = value;
  LightAccount account;
  account.energy = energy_ratio;
  account.lost = std::isfinite(lost_fraction) ? lost_fraction : 0.0;
  account.moved = std::isfinite(moved) ? std::clamp(moved, 0.0, std::max(0.0, account.lost)) : 0.0;
  std::map<std::string, double> needs;
  for (const auto& [pair, entry] : in_view["joint"].items()) {
    const double share = entry.value("share", 0.0);
    bool modelled = true, light_kind = false;
    for (const nlohmann::json& capability : entry.value("capabilities", nlohmann::json::array())) {
      const std::string name = capability.get<std::string>();
      if (declared.count(name) && !declared[name]) {
        modelled = false;
        needs[name] += share;
        for (int kind = 0; kind < kPathLights; ++kind)
          light_kind = light_kind || name == path_light_capability(static_cast<PathLight>(kind));
      }
    }
    if (!modelled) account.model += share;
    if (light_kind) account.substituted += share;
  }
  for (const auto& [name, share] : needs)
    if (share > 0.0) account.unmodelled.emplace_back(name, share);
  // Light that occluders block (a reference before the occlusion split has none to say).
  if (declared.count(kOcclusionCapability) && !declared[kOcclusionCapability] && in_view.contains("occlusion"))
    account.excess = std::max(0.0, in_view["occlusion"].value("excess", 0.0));
  std::stable_sort(account.unmodelled.begin(), account.unmodelled.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  // The energy the declarations and the lost flux account for is an interval: from delivering none of the
  // light in the unmodelled classes to delivering all of it (a method that does not model a class may still
  // put out an approximation of its light: csl's cones on a mirror), less the lost flux either way. The
  // lost flux and the model share may name the same light (a method that cannot place the light it does
  // not model may count it lost): together they explain at most all of it.
  const double lost = std::clamp(account.lost, 0.0, 1.0);
  // A light of a kind the method does not model is replaced by one it models (a distant light for a point
  // light), whose energy is not the reference's light's: beyond the tolerance, no upper bound.
  const double lowest = 1.0 - std::min(1.0, lost + account.model);
  const double highest = account.substituted > kUnexplainedLightTolerance ? std::numeric_limits<double>::infinity()
                                                                          : 1.0 - (lost - account.moved) + account.excess;
  account.unexplained = account.energy < lowest    ? lowest - account.energy
                        : account.energy > highest ? highest - account.energy
                                                   : 0.0;
  account.flagged = std::abs(account.unexplained) > kUnexplainedLightTolerance;
  return account;
}

namespace {

// The method's declarations as this build registers it; none for a method it does not (a plugin not loaded
// here): its declarations are unknown, so no account is given.
std::optional<Capabilities> declared_capabilities(const std::string& method) {
  try {
    return find_method(method).info().capabilities;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace

std::optional<LightAccount> account_for_record(const nlohmann::json& reference_record, const RunRecord& run) {
  const std::optional<double> energy = run.metric("energy_ratio");
  if (!energy || !std::isfinite(*energy) || run.empty_reference_frames) return std::nullopt;
  const std::optional<Capabilities> capabilities = declared_capabilities(run.method);
  if (!capabilities) return std::nullopt;
  double lost = 0.0, moved = 0.0;
  if (run.lost_flux) {
    auto mean = [](const std::vector<double>& values, double fallback) {
      size_t frames = 0;
      double sum = 0.0;
      for (double value : values)
        if (std::isfinite(value)) sum += value, ++frames;
      return frames ? sum / static_cast<double>(frames) : fallback;
    };
    lost = mean(run.lost_flux->frames, run.lost_flux->worst.fraction);
    moved = mean(run.lost_flux->moved_frames, run.lost_flux->moved_frames.empty() ? run.lost_flux->worst.moved : 0.0);
  }
  return account_for_light(reference_record, *capabilities, *energy, lost, moved);
}

std::vector<FrameLightAccount> frame_accounts(const nlohmann::json& reference_record, const RunRecord& run) {
  std::vector<FrameLightAccount> accounts;
  if (!reference_record.is_object() || run.empty_reference_frames) return accounts;
  const std::optional<Capabilities> capabilities = declared_capabilities(run.method);
  if (!capabilities) return accounts;
  const nlohmann::json& frames = reference_record.contains("frames") ? reference_record["frames"] : nlohmann::json();
  for (size_t i = 0; i < run.frames.size(); ++i) {
    const FrameRecord& frame = run.frames[i];
    auto energy = frame.metrics.find("energy_ratio");
    if (energy == frame.metrics.end() || !std::isfinite(energy->second)) continue;
    // This frame's split: record.json "frames" keyed by the frame's number, else the record's own (one frame).
    nlohmann::json split = reference_record;
    const std::string key = std::to_string(frame.frame);
    if (frames.is_object() && frames.contains(key) && frames[key].contains("path_classes"))
      split = nlohmann::json{{"path_classes", frames[key]["path_classes"]}};
    else if (reference_record.value("frame", frame.frame) != frame.frame)
      continue;  // no split for this frame
    const double lost = run.lost_flux && i < run.lost_flux->frames.size() && std::isfinite(run.lost_flux->frames[i])
                            ? run.lost_flux->frames[i]
                            : 0.0;
    const double moved = run.lost_flux && i < run.lost_flux->moved_frames.size() &&
                                 std::isfinite(run.lost_flux->moved_frames[i])
                             ? run.lost_flux->moved_frames[i]
                             : 0.0;
    if (std::optional<LightAccount> account = account_for_light(split, *capabilities, energy->second, lost, moved))
      accounts.push_back({frame.frame, *account});
  }
  return accounts;
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
  if (account.substituted > kUnexplainedLightTolerance)
    parts.push_back(fmt::format("replaces the {:.1f} % of a light kind it does not model with a light it models, "
                                "whose energy is not bounded by the reference's",
                                100.0 * account.substituted));
  if (account.excess >= 0.0005)
    parts.push_back(fmt::format("may add up to {:.1f} % that occluders block ({})", 100.0 * account.excess,
                                kOcclusionCapability));
  if (account.lost >= 0.0005) parts.push_back(fmt::format("loses {:.1f} % by its knobs", 100.0 * account.lost));
  if (account.flagged)
    parts.push_back(fmt::format("unexplained: {:.2f} of the light {}, not a declared limit", std::abs(account.unexplained),
                                account.unexplained > 0.0 ? "missing" : "in excess"));
  return join(parts, "; ") + fmt::format(" (energy {:.3f}, lost {:.3f}, model {:.3f}, unexplained {:+.3f})", account.energy,
                            account.lost, account.model, account.unexplained);
}

}  // namespace causticbench
