// The functions between the parts of the report pipeline (see report_model.h for the order), one block
// per source file: the stages that fill the Report, the pieces of text and tables that several writers
// share, and the writers themselves. Internal to reports/; the public interface is reports/report.h.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "reports/report_model.h"

namespace causticbench::report_detail {

// ---------------------------------------------------------------------------------------------------
// The stages, in the order write_report runs them.

// report_loading.cpp: experiment.json, environment.json, every run's record.json (a damaged one becomes
// a failed run), the metric columns, the scene variants and each variant's reference record. Throws
// InputError when `folder_text` is not an experiment results folder.
void load_report(Report& report, const std::string& folder_text);

// report_baselines.cpp: each variant's baselines (metrics/baselines.h) scored on the report's metrics
// against its reference images; a variant whose images cannot be read gets none, and a note says so.
void score_variant_baselines(Report& report);
// A run whose primary metric is no better than the black image's (ties count): it showed nothing the
// primary metric can see.
bool no_better_than_black(const Report& report, const Run& run);
// Per metric, how many of the ok scored runs the black image beats or ties, and how many were scored.
struct BlackWins {
  size_t beaten = 0, scored = 0;
};
std::map<std::string, BlackWins> black_wins(const Report& report);

// pareto_fronts.cpp: report.fronts, within each variant, on the primary metric against frame time.
void compute_fronts(Report& report);

// claims.cpp: report.claims, one per entry of experiment.json "claims".
void evaluate_claims(Report& report);

// report_images.cpp: the thumbnails, error maps and colour bar under <experiment>/report/, and
// report.thumbnails; the names of the files written are added to `written`.
void make_images(Report& report, std::set<std::string>& written);

// plots.cpp: report.plots (the trade-offs, reference convergence, one per swept knob).
void make_plots(Report& report);
// tradeoff_plots.cpp: one plot per trade-off with its fronts, and the total cost over N frames.
void make_tradeoff_plots(Report& report);

// ---------------------------------------------------------------------------------------------------
// tables.cpp: the tables that HTML and Markdown both show, as cells.

// A cell's text and whether it is the best of its column.
struct Cell {
  std::string text;
  bool best = false;
  bool numeric = false;
  bool warn = false;
  std::string undefined = {};  // why the cell has no value: shown as a footnote (and, in HTML, on hover)
  std::string link = {};       // HTML: the text links here (a relative URL)
  bool markdown = false;       // Markdown: the text is Markdown already, its user text escaped (md_text)
};

struct Table {
  std::vector<std::string> header;
  std::vector<std::string> header_notes;  // tooltip text for HTML headers (may be empty)
  std::vector<std::vector<Cell>> rows;
};

// The timing columns of the results table (record name, header), also the first of results.csv.
inline constexpr const char* kTimingColumns[][2] = {{"frame_ms_median", "frame ms median"},
                                                    {"update_ms_median", "update ms median"},
                                                    {"update_ms_min", "update ms min"},
                                                    {"render_ms_median", "render ms median"},
                                                    {"render_ms_min", "render ms min"}};

Table results_table(const Report& report);  // the ok runs, grouped by method
Table failed_table(const Report& report);   // the runs whose status is not ok
Table paper_table(const Report& report);    // experiment.json "paper": its values beside ours

// cost_tables.cpp: report.views (equal time, equal error, break-even per variant) and their tables.
void compute_views(Report& report);
Table equal_time_table(const Report& report, size_t variant);
Table equal_error_table(const Report& report, size_t variant);
Table break_even_table(const Report& report, size_t variant);
// Whether some variant has a point to compare, and what the three tables mean (plain text).
bool has_views(const Report& report);
std::string views_caption(const Report& report);
// A run's knobs that differ from its method's defaults as a person reads them ("its defaults" when none
// does: Run::changed_text), and a frame budget ("16.7 ms", "10 s"): how the views and the study's summary
// name them.
std::string knobs_of(const Run& run);
std::string budget_text(double ms);
// "Within 16.7 ms: ..." per budget (and variant): the summary's lines.
std::vector<std::string> budget_lines(const Report& report);

// A table in Markdown (markdown_writer.cpp) or HTML (html_writer.cpp), with the footnotes of its
// undefined cells and the best of each column marked; appended to `out`. The report and the study's
// summary (summary_documents.cpp) both lay their tables out with these.
void markdown_table(std::string& out, const Table& table);
void html_table(std::string& out, const Table& table);

// The distinct reasons of a table's undefined cells, in the order they first appear: its footnotes.
std::vector<std::string> undefined_notes(const Table& table);
// The footnote number (from 1) of `note`.
size_t note_number(const std::vector<std::string>& notes, const std::string& note);

// ---------------------------------------------------------------------------------------------------
// case_table.cpp: the extremes studies' table (experiment.json "case_table": true), every run as a row.

// One run as the case table shows it. outcome: finite, non-finite, stopped, empty reference or stale.
struct CaseRow {
  size_t run = 0;  // into Report::runs
  std::string variant, method, setting, outcome, message;
  std::optional<double> energy_ratio, primary, max_error, frame_ms;
};
std::string case_outcome(const Run& run);
std::vector<CaseRow> case_rows(const Report& report);  // by variant, then in the experiment's order
Table case_table(const Report& report);
std::string case_table_caption(const Report& report);  // the counts per outcome and what they mean
json case_table_json(const Report& report);            // results.json "case_table"
bool has_case_table(const Report& report);              // experiment.json asks for it

// ---------------------------------------------------------------------------------------------------
// claim_evidence.cpp: what the report says of each checked claim.

enum class Format { plain, markdown, html };

// Why the claim has its verdict, with the numbers that decided it.
std::string claim_evidence(const Report& report, const ClaimResult& result, Format format);
// The claim as experiment.json states it, with "verdict", "evidence" (plain text) and "details".
json claim_json(const Report& report, const ClaimResult& result);
// "3 of 4 claims confirmed (1 refuted).": the summary's line, empty without claims.
std::string claims_count_text(const Report& report);
// The report's claims counted by verdict.
ClaimCounts count_claims(const Report& report);

// ---------------------------------------------------------------------------------------------------
// findings.cpp: the summary at the top of the report.

// "relmse 0.012", "relmse undefined", or "empty reference": the primary metric under a run's picture.
std::string primary_caption(const Report& report, const Run& run);
// The experiment's facts beside the environment: source, scene, resolution, frames, references, ...
std::vector<std::pair<std::string, std::string>> experiment_facts(const Report& report);
// One-line findings: run counts, claims, and per variant the best, fastest, overall front, reference error.
std::vector<std::string> findings(const Report& report, bool html);

// ---------------------------------------------------------------------------------------------------
// The writers: each returns the whole file.

std::string markdown_document(const Report& report);  // markdown_writer.cpp: report.md
std::string html_document(const Report& report);      // html_writer.cpp: report.html
std::string viewer_document(const Report& report);    // viewer_page.cpp: viewer.html (when report.viewer has runs)
std::string results_csv(const Report& report);        // csv_writer.cpp: results.csv
std::string results_json(const Report& report);       // json_writer.cpp: results.json

}  // namespace causticbench::report_detail
