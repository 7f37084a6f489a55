#include "methods/method.h"

#include <fmt/format.h>

#include "core/errors.h"

namespace causticbench {

std::vector<std::pair<std::string, bool>> Capabilities::entries() const {
  return {{"reflection", reflection},
          {"refraction", refraction},
          {"multiple_bounces", multiple_bounces},
          {"directional_light", directional_light},
          {"point_light", point_light},
          {"environment_light", environment_light},
          {"moving_light", moving_light},
          {"moving_objects", moving_objects},
          {"occlusion", occlusion},
          {"non_lambertian_receivers", non_lambertian_receivers}};
}

std::string BrokenKnobRule::describe(const std::string& method) const {
  std::string names;
  for (size_t i = 0; i < rule->knobs.size(); ++i) {
    if (i > 0) names += i + 1 == rule->knobs.size() ? " and " : ", ";
    names += "'" + rule->knobs[i] + "'";
  }
  return fmt::format("knobs {} of {}: {}", names, method, problem);
}

std::optional<BrokenKnobRule> broken_knob_rule(const MethodInfo& info, const ParamSet& params) {
  for (const KnobRule& rule : info.knob_rules) {
    bool applies = true;
    for (const std::string& knob : rule.knobs) applies = applies && params.has(knob);
    if (!applies) continue;
    std::string problem = rule.problem(params);
    if (!problem.empty()) return BrokenKnobRule{&rule, problem};
  }
  return std::nullopt;
}

nlohmann::json lost_flux_json(const LostFlux& lost) {
  nlohmann::json out = {{"fraction", lost.fraction}, {"what", lost.what}, {"knob", lost.knob}, {"advice", lost.advice}};
  if (lost.moved != 0.0) out["moved"] = lost.moved;
  return out;
}

void require_specular_object(const Scene& scene, const std::string& needs) {
  if (!scene.has_specular_object()) throw InputError(fmt::format("{}: {}, and the scene has none", scene.source, needs));
}

std::string describe_lost_flux(const LostFlux& lost) {
  return fmt::format("loses {:.1f} % of the caustic flux ({}){}", 100.0 * lost.fraction, lost.what,
                     lost.advice.empty() ? "" : "; " + lost.advice);
}

}  // namespace causticbench
