// The run's resolved knobs, which the paper table (tables.cpp), the claims (claims.cpp) and the sweep
// plots match and group by; the knobs that differ from its method's defaults, and the name they give it.
#include "reports/report_model.h"

#include "experiments/experiment.h"
#include "methods/registry.h"
#include "reports/report_text.h"

namespace causticbench::report_detail {

json run_knobs(const Run& run) {
  json knobs = run.record.knobs();
  knobs["variant"] = run.variant;
  return knobs;
}

json knobs_changed_from_defaults(const RunRecord& record) {
  const MethodInfo* info = nullptr;
  try {
    info = &find_method(record.method).info();
  } catch (const std::exception&) {
    return record.swept.is_object() ? record.swept : json::object();  // a plugin this build has not loaded
  }
  json changed = json::object();
  for (const json* phase : {&record.build, &record.frame, &record.render}) {
    if (!phase->is_object()) continue;
    for (const auto& [name, value] : phase->items()) {
      const ParamSpec* spec = find_param_spec(info->params, name);
      // A family's knob (external's pass-through) has no default: it is there because it was set.
      if (spec && spec->name == name) {
        ParamSet declared;
        declared.set(name, spec->default_value);
        if (declared.to_json()[name] == value) continue;
      }
      changed[name] = value;
    }
  }
  return changed;
}

std::string Run::changed_text() const {
  std::string text;
  for (const auto& [name, value] : changed.items()) {
    std::string shown = value_text(value);
    // A long text (external's command) would make every cell that names the run unreadable.
    if (shown.size() > 40) shown = shown.substr(0, 37) + "...";
    text += (text.empty() ? "" : ", ") + name + "=" + shown;
  }
  return text.empty() ? "its defaults" : text;
}

std::string Run::name() const {
  const std::string knobs = changed_text();
  return changed.empty() ? entry : entry + " (" + knobs + ")";
}

}  // namespace causticbench::report_detail
