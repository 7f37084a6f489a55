// report.md: the report for a reader of Markdown (GitHub, an editor): the same sections and tables as
// report.html, the image grid linked from report/, and no plots.
#include <fmt/format.h>

#include <algorithm>

#include "core/errors.h"
#include "reports/capability_matrix.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

void markdown_table(std::string& out, const Table& table) {
  out += "|";
  for (const std::string& name : table.header) out += " " + md_escape(name) + " |";
  out += "\n|";
  for (size_t c = 0; c < table.header.size(); ++c) {
    bool numeric = !table.rows.empty() && std::all_of(table.rows.begin(), table.rows.end(), [&](const auto& row) {
      return c < row.size() && row[c].numeric;
    });
    out += numeric ? "--:|" : "---|";
  }
  out += "\n";
  const std::vector<std::string> notes = undefined_notes(table);
  for (const auto& row : table.rows) {
    out += "|";
    for (const Cell& cell : row) {
      const std::string escaped = cell.markdown ? md_table_cell(cell.text) : md_escape(cell.text);
      std::string text = cell.best ? "**" + escaped + "**" : escaped;
      if (!cell.undefined.empty()) text = fmt::format("\u2014 [{}]", note_number(notes, cell.undefined));
      out += " " + text + " |";
    }
    out += "\n";
  }
  out += "\n";
  for (size_t n = 0; n < notes.size(); ++n) out += fmt::format("- [{}] undefined: {}\n", n + 1, md_escape(notes[n]));
  if (!notes.empty()) out += "\n";
}

namespace {

// The equal-time, equal-error and break-even tables of each variant.
void views_markdown(std::string& out, const Report& report) {
  if (!has_views(report)) return;
  out += "## Equal time and equal error\n\n" + md_text(views_caption(report)) + "\n\n";
  for (size_t v = 0; v < report.views.size(); ++v) {
    if (report.views[v].points.empty()) continue;
    std::string in = report.multi() ? " (variant " + md_text(report.variants[v].name) + ")" : "";
    out += "### Equal time" + in + "\n\n";
    markdown_table(out, equal_time_table(report, v));
    out += "### Equal error" + in + "\n\n";
    markdown_table(out, equal_error_table(report, v));
    Table breaks = break_even_table(report, v);
    if (!breaks.rows.empty()) {
      out += "### Break-even" + in + "\n\n";
      markdown_table(out, breaks);
    }
  }
}

}  // namespace

std::string markdown_document(const Report& report) {
  std::string out;
  out += fmt::format("# causticbench report: {}\n\n", md_text(report.name));
  std::string description = string_member(report.experiment, "description");
  if (!description.empty()) out += md_text(description) + "\n\n";
  out += "Plots (trade-off, convergence, sweeps) are in report.html.\n\n";

  // A code block, fenced longer than any run of backticks in it and one line a value, so that no value
  // of environment.json can close it.
  std::vector<std::pair<std::string, std::string>> env;
  flatten(report.environment, "", env);
  size_t width = 0, longest = 0;
  std::string block;
  for (const auto& [key, value] : env) width = std::max(width, key.size());
  for (const auto& [key, value] : env) {
    std::string line = fmt::format("{:<{}}  {}", key + ":", width + 1, value);
    std::replace(line.begin(), line.end(), '\n', ' ');
    std::replace(line.begin(), line.end(), '\r', ' ');
    for (size_t run = 0, i = 0; i < line.size(); ++i) longest = std::max(longest, run = line[i] == '`' ? run + 1 : 0);
    block += line + "\n";
  }
  if (env.empty()) block += "(environment.json missing)\n";
  const std::string fence(std::max<size_t>(3, longest + 1), '`');
  out += "## Environment\n\n" + fence + "\n" + block + fence + "\n\n";

  out += "## Experiment\n\n";
  for (const auto& [key, value] : experiment_facts(report)) out += fmt::format("- {}: {}\n", md_text(key), md_text(value));
  out += "\n";
  for (const std::string& note : report.notes) out += "> **Note:** " + md_text(note) + "\n\n";
  out += "## Summary\n\n";
  for (const std::string& line : findings(report, false)) out += "- " + line + "\n";
  out += "\n";

  if (!report.claims.empty()) {
    out += "## Claims\n\n";
    out += "The paper's claims (experiment.json \"claims\") checked on the finished runs; see docs/reports.md.\n\n";
    Table claims;
    claims.header = {"claim", "verdict", "evidence"};
    for (const ClaimResult& result : report.claims)
      claims.rows.push_back({{string_member(result.claim, "text", "(no text)")},
                             {verdict_name(result.verdict)},
                             {claim_evidence(report, result, Format::markdown), false, false, false, {}, {}, true}});
    markdown_table(out, claims);
  }

  if (std::optional<CapabilityMatrix> matrix = report_capability_matrix(report)) out += capability_matrix_markdown(*matrix);

  out += "## Results\n\n";
  Table results = results_table(report);
  if (results.rows.empty())
    out += "No run finished.\n\n";
  else {
    out +=
        "Bold: best of its column (for metrics the direction is in the header: \u2193 lower is better, "
        "\u2191 higher, \u2192x closest to x); \u25c6: on the Pareto front over all methods.";
    if (report.multi()) out += " With several scene variants, best values and fronts are within each variant.";
    out += "\n\n";
    markdown_table(out, results);
  }
  if (has_case_table(report)) {
    out += "## Case table\n\n" + case_table_caption(report) + "\n\n";
    markdown_table(out, case_table(report));
  }
  views_markdown(out, report);
  Table failed = failed_table(report);
  if (!failed.rows.empty()) {
    out += report.stale_count() ? "## Failed and stale runs (not compared)\n\n" : "## Failed runs\n\n";
    markdown_table(out, failed);
  }
  if (!report.missing.empty()) {
    out += "## Runs not run yet\n\n" + md_text(join(report.missing, ", ")) + "\n\n";
  }
  const json& paper = member(report.experiment, "paper");
  if (paper.is_object()) {
    out += fmt::format("## Paper: {}\n\n", md_text(string_member(paper, "title", "published numbers")));
    markdown_table(out, paper_table(report));
  }
  if (!report.thumbnails.empty()) {
    out += "## Images\n\n";
    out += fmt::format(
        "E_c tone-mapped so that the reference's mean is {} grey{}; error = |test \u2212 reference| "
        "luminance, black = 0, yellow = {} or more.{}\n\n",
        kMiddleGrey, report.multi() ? " (each run exposed like, and compared with, its own variant's reference)" : "",
        report.error_scale_text.empty() ? "max" : report.error_scale_text,
        report.has_flip_maps ? " FLIP = the HDR-FLIP error map over the receivers, black = 0, pale yellow = 1." : "");
    out += report.has_flip_maps ? "| run | E_c | error | FLIP | |\n|---|---|---|---|---|\n"
                                : "| run | E_c | error | |\n|---|---|---|---|\n";
    for (const Thumbnail& thumb : report.thumbnails) {
      out += "| " + md_escape(thumb.title) + " | ";
      out += thumb.ec_png.empty() ? "" : "![" + md_escape(thumb.title) + "](report/" + thumb.ec_png + ")";
      out += " | ";
      out += thumb.error_png.empty() ? "" : "![error](report/" + thumb.error_png + ")";
      if (report.has_flip_maps) out += " | " + (thumb.flip_png.empty() ? "" : "![FLIP](report/" + thumb.flip_png + ")");
      out += " | " + md_escape(thumb.caption) + (thumb.note.empty() ? "" : "; " + md_escape(thumb.note)) + " |\n";
    }
    out += "\n";
  }
  out += "Files: [report.html](report.html), [results.csv](results.csv), [results.json](results.json).\n";
  return out;
}

}  // namespace causticbench::report_detail
