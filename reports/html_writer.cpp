// report.html: the whole report in one page that opens offline from disk. The style sheet and the
// script that draws the plots are reports/templates/report.css and plots.js, embedded at build time
// (reports/CMakeLists.txt); the Vega bundles load from report/vendor/ beside the page.
#include <fmt/format.h>

#include "core/errors.h"
#include "reports/capability_matrix.h"
#include "reports/report_parts.h"
#include "templates/plots.js.h"
#include "templates/report.css.h"

namespace causticbench::report_detail {

void html_table(std::string& out, const Table& table) {
  out += "<div class=\"scroll\"><table><thead><tr>";
  for (size_t c = 0; c < table.header.size(); ++c) {
    const std::string& note = c < table.header_notes.size() ? table.header_notes[c] : "";
    out += note.empty() ? "<th>" : "<th title=\"" + html_escape(note) + "\">";
    out += html_escape(table.header[c]) + "</th>";
  }
  out += "</tr></thead><tbody>\n";
  const std::vector<std::string> notes = undefined_notes(table);
  for (const auto& row : table.rows) {
    out += "<tr>";
    for (const Cell& cell : row) {
      std::string classes;
      if (cell.numeric)
        classes += " num";
      else if (cell.text.size() > 24)
        classes += " text";
      if (cell.best) classes += " best";
      if (cell.warn) classes += " warn";
      if (!cell.undefined.empty()) classes += " undefined";
      out += classes.empty() ? "<td" : "<td class=\"" + classes.substr(1) + "\"";
      if (!cell.undefined.empty()) {
        // No value, only the footnote's number; hovering shows the reason.
        out += " title=\"undefined: " + html_escape(cell.undefined) + "\">";
        out += fmt::format("<sup>{}</sup></td>", note_number(notes, cell.undefined));
        continue;
      }
      out += ">" + (cell.link.empty() ? html_escape(cell.text)
                                      : "<a href=\"" + html_escape(cell.link) + "\">" + html_escape(cell.text) + "</a>") +
             "</td>";
    }
    out += "</tr>\n";
  }
  out += "</tbody></table></div>\n";
  if (notes.empty()) return;
  out += "<ol class=\"undefined-notes\">";
  for (const std::string& note : notes) out += "<li>undefined: " + html_escape(note) + "</li>";
  out += "</ol>\n";
}

namespace {

// The equal-time, equal-error and break-even tables of each variant.
void views_html(std::string& out, const Report& report) {
  if (!has_views(report)) return;
  out += "<h2 id=\"views\">Equal time and equal error</h2>\n";
  for (size_t v = 0; v < report.views.size(); ++v) {
    if (report.views[v].points.empty()) continue;
    std::string in = report.multi() ? " (variant " + html_escape(report.variants[v].name) + ")" : "";
    out += "<h3>Equal time" + in + "</h3>\n";
    html_table(out, equal_time_table(report, v));
    out += "<h3>Equal error" + in + "</h3>\n";
    html_table(out, equal_error_table(report, v));
    Table breaks = break_even_table(report, v);
    if (!breaks.rows.empty()) {
      out += "<h3>Break-even" + in + "</h3>\n";
      html_table(out, breaks);
    }
  }
  out += "<p class=\"caption\">" + html_escape(views_caption(report)) + "</p>\n";
}

}  // namespace

std::string html_document(const Report& report) {
  std::string out;
  out += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + html_escape(report.name) + " \u2014 causticbench report</title>\n<style>\n" +
         std::string(kReportStyle) + "</style>\n";
  for (const char* file : kVendorFiles) out += fmt::format("<script src=\"report/vendor/{}\"></script>\n", file);
  out += "</head><body>\n";
  out += "<h1>causticbench report: " + html_escape(report.name) + "</h1>\n";
  std::string description = string_member(report.experiment, "description");
  if (!description.empty()) out += "<p class=\"description\">" + html_escape(description) + "</p>\n";
  out += "<nav><a href=\"#environment\">environment</a>";
  if (!report.claims.empty()) out += "<a href=\"#claims\">claims</a>";
  out += "<a href=\"#results\">results</a>";
  if (report.failed_count()) out += "<a href=\"#failed\">failed runs</a>";
  if (member(report.experiment, "paper").is_object()) out += "<a href=\"#paper\">paper</a>";
  if (!report.plots.empty()) out += "<a href=\"#plots\">plots</a>";
  if (!report.thumbnails.empty()) out += "<a href=\"#images\">images</a>";
  out +=
      "<a href=\"results.csv\">results.csv</a><a href=\"results.json\">results.json</a><a "
      "href=\"report.md\">report.md</a></nav>\n";

  out += "<h2 id=\"environment\">Environment</h2>\n<div class=\"columns\"><dl class=\"env\">";
  std::vector<std::pair<std::string, std::string>> env;
  flatten(report.environment, "", env);
  if (env.empty()) out += "<dt>environment</dt><dd>environment.json missing</dd>";
  for (const auto& [key, value] : env) out += "<dt>" + html_escape(key) + "</dt><dd>" + html_escape(value) + "</dd>";
  out += "</dl><dl class=\"env\">";
  for (const auto& [key, value] : experiment_facts(report))
    out += "<dt>" + html_escape(key) + "</dt><dd>" + html_escape(value) + "</dd>";
  out += "</dl></div>\n";
  for (const std::string& note : report.notes) out += "<div class=\"note\">" + html_escape(note) + "</div>\n";
  out += "<ul class=\"findings\">";
  for (const std::string& line : findings(report, true)) out += "<li>" + line + "</li>";
  out += "</ul>\n";

  if (!report.claims.empty()) {
    out += "<h2 id=\"claims\">Claims</h2>\n";
    out +=
        "<div class=\"scroll\"><table class=\"claims\"><thead><tr><th>claim</th><th>verdict</th><th>evidence</th>"
        "</tr></thead><tbody>\n";
    for (const ClaimResult& result : report.claims) {
      const char* badge = verdict_badge(result.verdict);
      out += "<tr><td class=\"claim\">" + html_escape(string_member(result.claim, "text", "(no text)")) +
             "<div class=\"kind\">" + html_escape(result.kind) + "</div></td><td><span class=\"badge " + badge + "\">" +
             html_escape(verdict_name(result.verdict)) + "</span></td><td class=\"evidence\">" +
             claim_evidence(report, result, Format::html) + "</td></tr>\n";
    }
    out += "</tbody></table></div>\n";
    out +=
        "<p class=\"caption\">The paper's claims (experiment.json \"claims\") checked on the finished runs: green "
        "confirmed, amber partly (true for some of the pairs or groups it covers, not for others), red refuted, "
        "slate not separated (with several seeds: the 95 % intervals of every pair overlap), grey not measured "
        "(too few finished runs match).</p>\n";
  }

  if (std::optional<CapabilityMatrix> matrix = report_capability_matrix(report)) out += capability_matrix_html(*matrix);

  out += "<h2 id=\"results\">Results</h2>\n";
  Table results = results_table(report);
  if (results.rows.empty())
    out += "<p>No run finished.</p>\n";
  else {
    html_table(out, results);
    out +=
        "<p class=\"caption\">Green: best of its column (metric direction in the header: \u2193 lower is better, "
        "\u2191 higher, \u2192x closest to x; hover a header for its definition). \u25c6: on the Pareto front over "
        "all methods. Timings are over the repetitions after one warm-up; metrics are means over frames.";
    if (report.multi())
      out +=
          " With several scene variants, best values and fronts are within each variant (a run competes "
          "only with runs of its own variant).";
    out += "</p>\n";
  }
  if (has_case_table(report)) {
    out += "<h2 id=\"cases\">Case table</h2>\n";
    html_table(out, case_table(report));
    out += "<p class=\"caption\">" + html_escape(case_table_caption(report)) + "</p>\n";
  }
  views_html(out, report);
  Table failed = failed_table(report);
  if (!failed.rows.empty()) {
    out += report.stale_count() ? "<h2 id=\"failed\">Failed and stale runs (not compared)</h2>\n"
                                : "<h2 id=\"failed\">Failed runs</h2>\n";
    html_table(out, failed);
  }
  if (!report.missing.empty())
    out += "<p class=\"note\">Not run yet: " + html_escape(join(report.missing, ", ")) + "</p>\n";

  const json& paper = member(report.experiment, "paper");
  if (paper.is_object()) {
    out += "<h2 id=\"paper\">Paper: " + html_escape(string_member(paper, "title", "published numbers")) + "</h2>\n";
    html_table(out, paper_table(report));
    out +=
        "<p class=\"caption\">Each paper row beside the run(s) of that method whose resolved build and render "
        "knobs contain the row's match values. Timings compare the median.</p>\n";
  }

  if (!report.plots.empty()) {
    out += "<h2 id=\"plots\">Plots</h2>\n<div class=\"plots\">\n";
    for (const Plot& plot : report.plots) {
      out += "<figure class=\"plot\"><div class=\"vega-plot\" id=\"" + plot.id +
             "\"></div><figcaption class=\"caption\">" + html_escape(plot.caption) + "</figcaption></figure>\n";
    }
    out += "</div>\n";
  }

  if (!report.thumbnails.empty()) {
    out += "<h2 id=\"images\">Images (first frame)</h2>\n";
    out += fmt::format(
        "<p class=\"caption\">Left: E<sub>c</sub>, exposed so that the reference's mean over the receiver "
        "pixels is {} ({}), sRGB. {}: |test \u2212 reference| as luminance, clamped before resizing.{}</p>\n",
        kMiddleGrey,
        report.multi() ? "one reference per scene variant; every run is exposed like, and compared with, the "
                         "reference of its own variant"
                       : "same exposure for every run",
        report.has_flip_maps ? "Middle" : "Right",
        report.has_flip_maps ? " Right: the HDR-FLIP error map over the receivers (0 to 1; its mean is the flip "
                               "column), shrunk."
                             : "");
    if (!report.viewer.empty()) {
      out += "<p class=\"caption\"><a href=\"viewer.html\">Look closer in the viewer</a>: every run at full "
             "resolution in half floats beside its reference, another run and its error (absolute, relative, FLIP), "
             "with exposure, tone curve, zoom to single pixels and a readout of E<sub>c</sub> in W/m\u00b2; a "
             "run's title opens it there.</p>\n";
    }
    if (!report.error_scale_text.empty()) {
      out += "<div class=\"bar\">error 0 <img src=\"report/error_colour_bar.png\" alt=\"inferno colour scale\"> " +
             html_escape(report.error_scale_text) + " or more</div>\n";
    }
    if (report.has_flip_maps) {
      out += "<div class=\"bar\">FLIP 0 <img src=\"report/flip_colour_bar.png\" alt=\"magma colour scale\"> 1</div>\n";
    }
    out += "<div class=\"grid\">\n";
    for (const Thumbnail& thumb : report.thumbnails) {
      // Three pictures (E_c, |delta|, FLIP) need a wider card than two.
      out += std::string("<div class=\"card") + (thumb.reference ? " reference" : "") +
             (thumb.flip_png.empty() ? "" : " triple") + "\"><div class=\"title\">" +
             (thumb.viewer_id.empty()
                  ? html_escape(thumb.title)
                  : "<a href=\"viewer.html#run=" + html_escape(thumb.viewer_id) + "\">" + html_escape(thumb.title) + "</a>") +
             "</div><div class=\"pair\">";
      if (!thumb.ec_png.empty())
        out += "<div><img src=\"report/" + thumb.ec_png + "\" alt=\"E_c " + html_escape(thumb.title) +
               "\"><div class=\"label\">E<sub>c</sub></div></div>";
      if (!thumb.error_png.empty())
        out += "<div><img src=\"report/" + thumb.error_png + "\" alt=\"error " + html_escape(thumb.title) +
               "\"><div class=\"label\">" +
               (thumb.reference ? std::string("estimated error") : std::string("|test \u2212 reference|")) + "</div></div>";
      if (!thumb.flip_png.empty())
        out += "<div><img src=\"report/" + thumb.flip_png + "\" alt=\"FLIP " + html_escape(thumb.title) +
               "\"><div class=\"label\">FLIP</div></div>";
      out += "</div><div class=\"cap\">" + html_escape(thumb.caption) +
             (thumb.note.empty() ? "" : "<br>" + html_escape(thumb.note)) + "</div></div>\n";
    }
    out += "</div>\n";
  }

  out +=
      "<footer>Written by <code>causticbench report</code> from the stored runs only. Plots: Vega-Lite, rendered "
      "offline by the bundles in report/vendor/.</footer>\n";

  if (!report.plots.empty()) {
    out += "<script>\nconst causticbenchPlots = [\n";
    for (const Plot& plot : report.plots) out += "  [\"" + plot.id + "\", " + script_json(plot.spec) + "],\n";
    out += "];\n" + std::string(kPlotScript) + "</script>\n";
  }
  out += "</body></html>\n";
  return out;
}

}  // namespace causticbench::report_detail
