// "What this scene requires" (issue 52): the reference's caustic light in view split into light-path
// classes (methods/reference/path_class_tally.h), as one sentence of the report's findings.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace causticbench::report_detail {

// From a reference record (its "path_classes"): "95.7 % (± 0.004) one pass through a refracting object
// (refraction), 4.0 % (± 0.004) one reflection (reflection); light: 100.0 % (± 0) directional", then, where
// the scene has them, "receivers: 60.0 % (± 0.1) non_lambertian, ..." and "occluders block 23.0 % (± 0.2) of
// the light that would arrive without them (occlusion)"; classes
// in falling share, standard errors in percentage points to two digits,
// those below 0.05 % left out. Nothing when the record has no split (a reference computed before it was
// measured) or no caustic light in view.
std::optional<std::string> scene_requirements_text(const nlohmann::json& reference_record);

}  // namespace causticbench::report_detail
