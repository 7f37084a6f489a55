// The report's "Capability matrix" (declared in capability_matrix.h; docs/reports.md, "Capability
// matrix").
#include "reports/capability_matrix.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "experiments/experiment.h"
#include "reports/report_model.h"

namespace causticbench {

using nlohmann::json;
using report_detail::html_escape;
using report_detail::md_escape;
using report_detail::num;

namespace {

std::string mark(const std::optional<bool>& value) { return !value ? "\u2014" : *value ? "\u2713" : "\u2717"; }
std::string yes_no(bool value) { return value ? "true" : "false"; }

// The one run of `method` on `variant` that `filter` selects (any, when it is empty). More than one is
// refused when the experiment is read; this takes the first.
CapabilityMeasurement measure(const std::vector<CapabilityRun>& runs, const std::string& method, const std::string& variant,
                              const std::string& filter) {
  CapabilityMeasurement out;
  for (const CapabilityRun& run : runs) {
    if (run.method != method || run.variant != variant) continue;
    if (!filter.empty() && !matches_filter(run.method, run.label, run.knobs, filter)) continue;
    out.found = true;
    out.energy_ratio = run.energy_ratio;
    out.relmse = run.relmse;
    out.error = run.failed ? run.error : "";
    out.verdict = judge_capability(run.failed && !run.nonfinite, run.energy_ratio, run.relmse);
    break;
  }
  return out;
}

std::string values_text(const CapabilityMeasurement& m) {
  if (!m.found) return "not run";
  if (m.verdict == CapabilityVerdict::refused) return "refused";
  auto value = [](const std::optional<double>& v) { return v ? num(*v) : std::string("undefined"); };
  return fmt::format("energy {}, relMSE {}", value(m.energy_ratio), value(m.relmse));
}

// The disagreements of one cell, each a line that says which two sources differ and by what.
std::vector<std::string> disagreements(const std::string& table, const CapabilityRow& row, const CapabilityCell& cell) {
  std::vector<std::string> flags;
  const std::string who = cell.method + " " + row.capability;
  if (cell.published && cell.declared && *cell.published != *cell.declared)
    flags.push_back(fmt::format("{}: {} {} it, the code declares {}{}", who, table, *cell.published ? "marks" : "does not mark",
                                yes_no(*cell.declared), cell.note.empty() ? "" : " (" + cell.note + ")"));
  if (!cell.judged || !cell.with.found || cell.with.verdict == CapabilityVerdict::neither) return flags;
  const std::string measured = fmt::format("measured {} ({}; without the difficulty: {})",
                                           capability_verdict_name(cell.with.verdict), values_text(cell.with),
                                           values_text(cell.without));
  if (cell.declared && !capability_verdict_agrees(*cell.declared, cell.with.verdict))
    flags.push_back(fmt::format("{}: declared {}, {}", who, yes_no(*cell.declared), measured));
  if (cell.published && !capability_verdict_agrees(*cell.published, cell.with.verdict))
    flags.push_back(fmt::format("{}: {} {} it, {}", who, table, *cell.published ? "marks" : "does not mark", measured));
  return flags;
}

std::string cell_text(const CapabilityCell& cell) {
  std::string text = mark(cell.published) + " " + mark(cell.declared) + " ";
  if (!cell.with.found) return text + "not run";
  text += capability_verdict_name(cell.with.verdict);
  if (!cell.judged) text += " (not judged)";
  if (cell.with.verdict != CapabilityVerdict::refused) {
    auto value = [](const std::optional<double>& v) { return v ? num(*v) : std::string("\u2014"); };
    text += fmt::format(": {} / {}", value(cell.with.energy_ratio), value(cell.with.relmse));
  }
  if (cell.without.found) {
    if (cell.without.verdict == CapabilityVerdict::refused)
      text += "; without: refused";
    else
      text += fmt::format("; without: {} / {}", cell.without.energy_ratio ? num(*cell.without.energy_ratio) : "\u2014",
                          cell.without.relmse ? num(*cell.without.relmse) : "\u2014");
  }
  return text;
}

std::string caption(const CapabilityMatrix& matrix) {
  return fmt::format(
      "Per method: {} ({} marked, {} not, \u2014 no row or column), declared (the code's Capabilities, "
      "`causticbench list`), and the verdict measured on the case's scene: energy ratio / relMSE against the "
      "reference, then on its twin without the difficulty. Rule: {}. A declared capability must hold, a denied "
      "one must be refused or wrong; \"not judged\": the scene is built on a capability the method declares false "
      "(reflection, for the mirror sphere's cases). Flagged cells (!) are listed below.",
      matrix.title.empty() ? "published" : "published (" + matrix.title + ")", "\u2713", "\u2717", capability_rule_text());
}

}  // namespace

CapabilityMatrix build_capability_matrix(const json& settings, const std::vector<CapabilityRun>& runs,
                                         const std::map<std::string, double>& reference_errors) {
  CapabilityMatrix matrix;
  const json& published = report_detail::member(settings, "published");
  matrix.title = report_detail::string_member(published, "title");
  const json& declared = report_detail::member(settings, "declared");
  if (declared.is_object())
    for (const auto& [method, value] : declared.items()) matrix.methods.push_back(method);
  const json& select = report_detail::member(settings, "select");
  const json& cases = report_detail::member(settings, "cases");
  if (!cases.is_array()) return matrix;
  for (const json& entry : cases) {
    CapabilityRow row;
    row.capability = report_detail::string_member(entry, "capability");
    row.with = report_detail::string_member(entry, "with");
    row.without = report_detail::string_member(entry, "without");
    row.built_on = report_detail::string_member(entry, "built_on");
    const json& table_rows = report_detail::member(report_detail::member(published, "rows"), row.capability);
    if (table_rows.is_array())
      for (const json& name : table_rows) row.table_rows.push_back(name.is_string() ? name.get<std::string>() : "");
    for (const std::string& method : matrix.methods) {
      CapabilityCell cell;
      cell.method = method;
      const json& column = report_detail::member(report_detail::member(published, "methods"), method);
      if (!table_rows.is_null() && column.is_array())
        cell.published = std::find(column.begin(), column.end(), json(row.capability)) != column.end();
      const json& capabilities = report_detail::member(report_detail::member(declared, method), "capabilities");
      if (capabilities.contains(row.capability) && capabilities[row.capability].is_boolean())
        cell.declared = capabilities[row.capability].get<bool>();
      cell.note = report_detail::string_member(report_detail::member(declared[method], "notes"), row.capability);
      if (!row.built_on.empty()) cell.judged = report_detail::member(capabilities, row.built_on) != json(false);
      const std::string filter = report_detail::string_member(
          report_detail::member(entry, "select"), method, report_detail::string_member(select, method));
      cell.with = measure(runs, method, row.with, filter);
      cell.without = measure(runs, method, row.without, filter);
      cell.flags = disagreements(matrix.title.empty() ? "the published table" : matrix.title, row, cell);
      row.cells.push_back(std::move(cell));
    }
    for (const std::string& variant : {row.with, row.without}) {
      auto floor = reference_errors.find(variant);
      if (floor != reference_errors.end() && floor->second > kCapabilityReferenceNoiseLimit)
        matrix.notes.push_back(fmt::format("the reference of {} has a reference error of {}, above {} (a tenth of the relMSE "
                                           "bound): its verdicts are uncertain",
                                           variant, num(floor->second), num(kCapabilityReferenceNoiseLimit)));
    }
    matrix.rows.push_back(std::move(row));
  }
  return matrix;
}

std::string capability_matrix_markdown(const CapabilityMatrix& matrix, const std::string& heading) {
  std::string out = "## " + md_escape(heading) + "\n\n" + md_escape(caption(matrix)) + "\n\n| capability | published rows |";
  for (const std::string& method : matrix.methods) out += " " + md_escape(method) + " |";
  out += "\n|---|---|";
  for (size_t m = 0; m < matrix.methods.size(); ++m) out += "---|";
  out += "\n";
  std::vector<std::string> flags;
  for (const CapabilityRow& row : matrix.rows) {
    out += "| " + md_escape(row.capability) + " | " +
           md_escape(row.table_rows.empty() ? "\u2014" : join(row.table_rows, "; ")) + " |";
    for (const CapabilityCell& cell : row.cells) {
      out += " " + md_escape(cell_text(cell));
      for (const std::string& flag : cell.flags) {
        flags.push_back(flag);
        out += fmt::format(" (!{})", flags.size());
      }
      out += " |";
    }
    out += "\n";
  }
  out += "\n";
  if (flags.empty()) out += "Declaration, paper and measurement agree everywhere.\n\n";
  for (size_t i = 0; i < flags.size(); ++i) out += fmt::format("- (!{}) {}\n", i + 1, md_escape(flags[i]));
  for (const std::string& note : matrix.notes) out += "- Note: " + md_escape(note) + "\n";
  return out + "\n";
}

std::string capability_matrix_html(const CapabilityMatrix& matrix, const std::string& heading) {
  std::string out = "<h2 id=\"capabilities\">" + html_escape(heading) + "</h2>\n<div class=\"scroll\"><table><thead><tr>"
                    "<th>capability</th><th>published rows</th>";
  for (const std::string& method : matrix.methods) out += "<th>" + html_escape(method) + "</th>";
  out += "</tr></thead><tbody>\n";
  std::vector<std::string> flags;
  for (const CapabilityRow& row : matrix.rows) {
    out += "<tr><td>" + html_escape(row.capability) + "</td><td>" +
           html_escape(row.table_rows.empty() ? "\u2014" : join(row.table_rows, "; ")) + "</td>";
    for (const CapabilityCell& cell : row.cells) {
      out += cell.flags.empty() ? "<td>" : "<td class=\"warn\" title=\"" + html_escape(join(cell.flags, "\n")) + "\">";
      out += html_escape(cell_text(cell));
      for (const std::string& flag : cell.flags) {
        flags.push_back(flag);
        out += fmt::format(" (!{})", flags.size());
      }
      out += "</td>";
    }
    out += "</tr>\n";
  }
  out += "</tbody></table></div>\n<p class=\"caption\">" + html_escape(caption(matrix)) + "</p>\n<ul>";
  if (flags.empty()) out += "<li>Declaration, paper and measurement agree everywhere.</li>";
  for (size_t i = 0; i < flags.size(); ++i) out += fmt::format("<li>(!{}) {}</li>", i + 1, html_escape(flags[i]));
  for (const std::string& note : matrix.notes) out += "<li>Note: " + html_escape(note) + "</li>";
  return out + "</ul>\n";
}

json capability_matrix_json(const CapabilityMatrix& matrix) {
  auto optional = [](const auto& value) { return value ? json(*value) : json(nullptr); };
  auto measurement = [&](const CapabilityMeasurement& m) {
    return json{{"found", m.found},
                {"verdict", m.found ? json(capability_verdict_name(m.verdict)) : json(nullptr)},
                {"energy_ratio", optional(m.energy_ratio)},
                {"relmse", optional(m.relmse)},
                {"error", m.error}};
  };
  json rows = json::array();
  for (const CapabilityRow& row : matrix.rows) {
    json methods = json::object();
    for (const CapabilityCell& cell : row.cells) {
      methods[cell.method] = {{"published", optional(cell.published)}, {"declared", optional(cell.declared)},
                              {"note", cell.note},       {"judged", cell.judged},
                              {"with", measurement(cell.with)}, {"without", measurement(cell.without)},
                              {"flags", cell.flags}};
    }
    rows.push_back({{"capability", row.capability}, {"with", row.with}, {"without", row.without},
                    {"built_on", row.built_on}, {"table_rows", row.table_rows}, {"methods", methods}});
  }
  return {{"title", matrix.title}, {"rule", capability_rule_text()}, {"methods", matrix.methods}, {"rows", rows},
          {"notes", matrix.notes}};
}

namespace report_detail {

std::optional<CapabilityMatrix> report_capability_matrix(const Report& report) {
  const json& settings = member(report.experiment, "capability_matrix");
  if (!settings.is_object()) return std::nullopt;
  std::vector<CapabilityRun> runs;
  for (const Run& run : report.runs) {
    if (run.stale) continue;  // measured against another reference
    CapabilityRun out;
    out.method = run.method;
    out.variant = run.variant;
    out.label = run.label;
    out.knobs = run_knobs(run);
    out.failed = !run.ok;
    out.nonfinite = run.record.metric("nonfinite_pixels").value_or(0.0) > 0.0;
    out.error = run.error;
    out.energy_ratio = run.metric("energy_ratio");
    out.relmse = run.metric("relmse");
    // The judged frame's values (`frame`; experiment.json written before it has none: the mean over
    // the frames), so that a moving case is judged where it has moved and not diluted by its rest pose.
    if (settings.contains("frame") && settings["frame"].is_number_integer()) {
      const int judged = settings["frame"].get<int>();
      for (const FrameRecord& frame : run.record.frames) {
        if (frame.frame != judged) continue;
        auto value = [&](const std::string& name) -> std::optional<double> {
          if (frame.metrics_undefined.count(name) || !run.undefined_reason(name).empty()) return std::nullopt;
          auto found = frame.metrics.find(name);
          if (found == frame.metrics.end() || std::isnan(found->second)) return std::nullopt;
          return found->second;
        };
        out.energy_ratio = value("energy_ratio");
        out.relmse = value("relmse");
      }
    }
    runs.push_back(std::move(out));
  }
  std::map<std::string, double> reference_errors;
  for (const Variant& variant : report.variants)
    if (variant.reference_error) reference_errors[variant.name] = *variant.reference_error;
  return build_capability_matrix(settings, runs, reference_errors);
}

}  // namespace report_detail

}  // namespace causticbench
