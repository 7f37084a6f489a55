#include "methods/describe.h"

#include <fmt/format.h>

namespace causticbench {

namespace {

std::string applies_text(const ParamSpec& spec) {
  return spec.applies_when ? "when " + spec.condition_text() : "always";
}

std::string shown_name(const ParamSpec& spec) { return spec.family ? spec.name + "<name>" : spec.name; }

// A family has no default; an empty text default is "none" (a knob that must be set).
std::string shown_default(const ParamSpec& spec) {
  std::string value = format_param_value(spec.default_value);
  return spec.family || value.empty() ? "none" : value;
}

}  // namespace

std::string describe_markdown(const MethodInfo& info) {
  std::string out = fmt::format("# `{}`\n\n{}\n\nPaper: {}\n\n", info.name, info.summary, info.paper);
  out += "| knob | phase | type | default | allowed | applies | meaning |\n|---|---|---|---|---|---|---|\n";
  for (const ParamSpec& spec : info.params) {
    out += fmt::format("| `{}` | {} | {} | `{}` | {} | {} | {} |\n", shown_name(spec), phase_name(spec.phase), spec.type_name(),
                       shown_default(spec), spec.range_text(), applies_text(spec), spec.meaning);
  }
  out += "\n## Capabilities\n\n| capability | supported |\n|---|---|\n";
  for (const auto& [capability, value] : info.capabilities.entries()) {
    out += fmt::format("| {} | {} |\n", capability, value ? "yes" : "no");
  }
  if (!info.capabilities.notes.empty()) {
    out += "\nNotes:\n\n";
    for (const auto& [capability, note] : info.capabilities.notes) out += fmt::format("- {}: {}\n", capability, note);
  }
  return out;
}

std::string describe_text(const MethodInfo& info) {
  std::string out = fmt::format(
      "{}: {}\npaper: {}\n\nknobs (build knobs feed prepare(), frame knobs update(), render knobs render()):\n", info.name,
      info.summary, info.paper);
  for (const ParamSpec& spec : info.params) {
    out += fmt::format("  {:<24} {:<6} {:<8} default {:<10} allowed {}{}\n      {}\n", shown_name(spec), phase_name(spec.phase),
                       spec.type_name(), shown_default(spec), spec.range_text(),
                       spec.applies_when ? "; applies when " + spec.condition_text() : "", spec.meaning);
  }
  out += "\ncapabilities:\n";
  for (const auto& [capability, value] : info.capabilities.entries()) {
    out += fmt::format("  {:<26} {}\n", capability, value ? "yes" : "no");
  }
  for (const auto& [capability, note] : info.capabilities.notes) out += fmt::format("  note: {}: {}\n", capability, note);
  return out;
}

}  // namespace causticbench
