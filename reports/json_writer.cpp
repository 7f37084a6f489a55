// results.json: the stored records in the current version's form (with the variant and reference filled in where an
// older record lacks them), the variants with their references, the Pareto fronts and the checked
// claims, for scripts (docs/reports.md, "Outputs").
#include "reports/capability_matrix.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

std::string results_json(const Report& report) {
  // The records as stored, with the variant and reference each was compared with filled in when an older
  // record lacks them (receiver_pixels then null).
  json runs = json::array();
  for (const Run& run : report.runs) {
    json record = run.record.to_json();
    if (run.record.variant.empty()) record["variant"] = run.variant;
    if (run.record.reference_key.empty()) record["reference_key"] = run.reference_key;
    if (!run.record.receiver_pixels) record["receiver_pixels"] = nullptr;
    if (run.stale) record["stale"] = run.error;
    // Where its light went (Run::light_account), against its variant's reference, then each frame's.
    if (const std::optional<LightAccount>& account = run.light_account) {
      json unmodelled = json::object();
      for (const auto& [capability, share] : account->unmodelled) unmodelled[capability] = share;
      json frames = json::array();
      for (const FrameLightAccount& frame : run.frame_light_accounts)
        frames.push_back({{"frame", frame.frame},
                          {"energy", frame.account.energy},
                          {"lost", frame.account.lost},
                          {"model", frame.account.model},
                          {"excess", frame.account.excess},
                          {"unexplained", frame.account.unexplained},
                          {"flagged", frame.account.flagged}});
      record["light_account"] = {{"energy", account->energy}, {"lost", account->lost}, {"model", account->model},
                                 {"excess", account->excess}, {"substituted", account->substituted},
                                 {"unexplained", account->unexplained}, {"flagged", account->flagged},
                                 {"unmodelled", unmodelled}, {"frames", frames}};
    }
    runs.push_back(record);
  }
  auto keys = [&](const std::vector<size_t>& indices) {
    json out = json::array();
    for (size_t i : indices) out.push_back(report.runs[i].key);
    return out;
  };
  // Fronts are computed within each variant; "overall" and "per_method" list every variant's, in order.
  json fronts = json::object(), per_variant = json::object(), variants = json::array();
  for (size_t v = 0; v < report.variants.size(); ++v) {
    const Variant& variant = report.variants[v];
    json methods = json::object();
    for (const auto& [method, front] : report.fronts[v].per_method) {
      methods[method] = keys(front);
      if (!fronts.contains(method)) fronts[method] = json::array();
      for (size_t i : front) fronts[method].push_back(report.runs[i].key);
    }
    per_variant[variant.name] = {{"overall", keys(report.fronts[v].overall)}, {"per_method", methods}};
    variants.push_back({{"name", variant.name},
                        {"reference_key", variant.reference_key},
                        {"resolution", variant.resolution},
                        {"overrides", variant.overrides},
                        {"listed", variant.listed},
                        {"error_estimate", variant.reference_error ? json(*variant.reference_error) : json(nullptr)},
                        {"reference", variant.reference}});
  }
  const Variant& first = report.variants.front();
  json out = {{"experiment", report.experiment},
              {"environment", report.environment},
              {"runs", runs},
              {"missing_runs", report.missing},
              {"reference", {{"key", first.reference_key}, {"record", first.reference}}},
              {"variants", variants},
              {"pareto_front",
               {{"metric", report.primary},
                {"time", "timings.frame_ms_median"},
                {"overall", keys(report.overall_fronts())},
                {"per_method", fronts},
                {"per_variant", per_variant}}}};
  json claims = json::array();
  for (const ClaimResult& result : report.claims) claims.push_back(claim_json(report, result));
  out["claims"] = claims;
  if (has_case_table(report)) out["case_table"] = case_table_json(report);
  if (std::optional<CapabilityMatrix> matrix = report_capability_matrix(report))
    out["capability_matrix"] = capability_matrix_json(*matrix);
  return out.dump(2) + "\n";
}

}  // namespace causticbench::report_detail
