#include "reports/scene_requirements.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"
#include "experiments/light_account.h"

namespace causticbench::report_detail {

namespace {

const char* describe_interaction(const std::string& name) {
  if (name == "one_reflection") return "one reflection";
  if (name == "one_pass") return "one pass through a refracting object";
  return "multiple bounces";
}

// "96.4 % (± 0.045)" for a share and its standard error (percentage points); the error left out where unknown.
std::string percent(const nlohmann::json& entry) {
  const double share = entry.value("share", 0.0);
  const nlohmann::json& error = entry.contains("standard_error") ? entry["standard_error"] : nlohmann::json();
  std::string text = fmt::format("{:.1f} %", 100.0 * share);
  // Two significant digits: the split of a converged reference is often known to a few hundredths of a percent.
  if (error.is_number()) text += fmt::format(" (\u00b1 {:.2g})", 100.0 * error.get<double>());
  return text;
}

// The classes of one grouping ("interaction" or "light"), largest share first, those above 0.05 %.
std::vector<std::string> listed(const nlohmann::json& group, bool interaction) {
  std::vector<std::pair<double, std::string>> entries;
  if (!group.is_object()) return {};
  for (const auto& [name, entry] : group.items()) {
    const double share = entry.value("share", 0.0);
    if (share < 0.0005) continue;
    const std::string what = interaction ? fmt::format("{} ({})", describe_interaction(name),
                                                       entry.value("capability", std::string()))
                                         : name;
    entries.emplace_back(share, percent(entry) + " " + what);
  }
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::string> texts;
  for (const auto& [share, text] : entries) texts.push_back(text);
  return texts;
}

}  // namespace

std::optional<std::string> scene_requirements_text(const nlohmann::json& reference_record) {
  const nlohmann::json* found = reference_light_in_view(reference_record);
  if (!found) return std::nullopt;
  const nlohmann::json& in_view = *found;
  const std::vector<std::string> interactions = listed(in_view.value("interaction", nlohmann::json()), true);
  const std::vector<std::string> lights = listed(in_view.value("light", nlohmann::json()), false);
  if (interactions.empty()) return std::nullopt;
  std::string text = join(interactions, ", ") + (lights.empty() ? "" : "; light: " + join(lights, ", "));
  // Receivers and occluders only where the scene has them (a record before their split has neither).
  const nlohmann::json receivers = in_view.value("receiver", nlohmann::json());
  if (receivers.is_object() && receivers.contains("non_lambertian") &&
      receivers["non_lambertian"].value("share", 0.0) >= 0.0005)
    text += "; receivers: " + join(listed(receivers, false), ", ");
  const nlohmann::json occlusion = in_view.value("occlusion", nlohmann::json());
  if (occlusion.is_object() && occlusion.value("share", 0.0) >= 0.0005)
    text += "; occluders block " + percent(occlusion) + " of the light that would arrive without them (occlusion)";
  return text;
}

}  // namespace causticbench::report_detail
