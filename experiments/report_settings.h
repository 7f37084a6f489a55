// What an experiment file tells the report (docs/experiment-format.md, "What the report compares"): the
// paper's published numbers, the claims to check, the trade-offs to draw, and the budgets and error
// targets of the equal-time and equal-error views. Every quantity they name is checked against the
// quantity registry (quantity_registry.h) when the experiment is read.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace causticbench {

class ConfigNode;

// Frame-time budgets of the equal-time view, ms: 60 Hz, 30 Hz, 10 Hz, interactive, offline.
inline const std::vector<double> kDefaultBudgetsMs = {16.7, 33.3, 100.0, 1000.0, 10000.0};
// Frame counts of the total-cost view (prepare + N x frame time): one frame, one second, one minute
// and one hour at 60 frames per second.
inline const std::vector<double> kDefaultTotalCostFrames = {1.0, 60.0, 3600.0, 216000.0};

struct ReportSettings {
  nlohmann::json paper;                                     // null when absent
  nlohmann::json claims = nlohmann::json::array();          // the paper's claims the report checks
  std::vector<std::pair<std::string, std::string>> tradeoffs;  // (x, y); default {(frame_ms, primary)}
  std::vector<double> budgets_ms = kDefaultBudgetsMs;
  std::vector<double> error_targets;  // of the primary metric; empty: chosen from the runs (docs/reports.md)
  std::vector<double> total_cost_frames = kDefaultTotalCostFrames;
  // `case_table: true`: the report adds the case table (reports/case_table.cpp), every run as one row of
  // case (scene variant) and method setting with its outcome: finite, non-finite, stopped with an error,
  // or against an empty reference. The extremes studies set it.
  bool case_table = false;
  // `capability_matrix` (experiments/capability_matrix_settings.h): the published matrix, the cases and
  // the methods' declared capabilities; null when the experiment declares none.
  nlohmann::json capability_matrix;

  nlohmann::json tradeoffs_json() const;
};

// Reads paper, claims, tradeoffs, budgets_ms, error_targets and total_cost_frames of an experiment's root
// map. A metric a claim or trade-off names must be one the experiment measures (`metrics`); any other
// quantity must be registered: unknown names fail with the closest known one. A paper row's
// `match: {variant: NAME}` must name one of `variants`.
ReportSettings read_report_settings(const ConfigNode& root, const std::vector<std::string>& metrics,
                                    const std::string& primary_metric, const std::vector<std::string>& variants);

}  // namespace causticbench
