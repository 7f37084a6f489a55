// The summary at the top of report.html and report.md: the experiment's facts beside the environment,
// and the one-line findings (run counts, claims, and per variant the best and fastest run, the front
// over all methods and whether the reference's estimated error sits well below the best relMSE).
#include <map>

#include <fmt/format.h>

#include "core/errors.h"
#include "reports/report_parts.h"
#include "reports/scene_requirements.h"

namespace causticbench::report_detail {

// "relmse 0.012", "relmse undefined", or "empty reference": the primary metric under a run's picture.
std::string primary_caption(const Report& report, const Run& run) {
  if (run.empty_reference) return "empty reference";
  if (auto value = run.metric(report.primary)) {
    const std::optional<MetricInterval> interval = run.interval(report.primary);
    if (report.seeds > 1 && interval) return report.primary + " " + num(*value) + " \u00b1 " + num(interval->half_width);
    return report.primary + " " + num(*value);
  }
  return report.primary + (run.undefined_reason(report.primary).empty() ? " \u2014" : " undefined");
}

std::vector<std::pair<std::string, std::string>> experiment_facts(const Report& report) {
  std::vector<std::pair<std::string, std::string>> facts;
  auto add = [&](const std::string& name, const json& value) {
    if (!value.is_null()) {
      std::vector<std::pair<std::string, std::string>> flat;
      flatten(value, name, flat);
      for (auto& entry : flat) facts.push_back(entry);
    }
  };
  add("source", member(report.experiment, "source"));
  add("scene", member(report.experiment, "scene"));
  auto resolution_text = [](const json& resolution) {
    return resolution.is_array() && resolution.size() == 2
               ? value_text(resolution[0]) + " x " + value_text(resolution[1])
               : std::string();
  };
  auto reference_text = [](const Variant& variant) {
    std::string text = variant.reference_key;
    if (variant.reference_error) text += ", reference error " + num(*variant.reference_error);
    const json& passes = member(variant.reference, "passes");
    if (passes.is_number()) text += ", " + value_text(passes) + " passes";
    const json& seconds = member(variant.reference, "seconds");
    if (seconds.is_number()) text += ", " + num(seconds.get<double>()) + " s";
    if (member(variant.reference, "converged") == false) text += ", NOT converged (stopped on its time cap)";
    return text;
  };
  std::string resolution = resolution_text(member(report.experiment, "resolution"));
  if (!report.multi() && !resolution.empty()) facts.push_back({"resolution", resolution});
  // The frame indices measured, with their count: "frames: 0" read as "no frames".
  if (const json& frames = member(report.experiment, "frames"); frames.is_array()) {
    std::vector<std::string> indices;
    for (const json& frame : frames) indices.push_back(value_text(frame));
    facts.push_back({"frames", fmt::format("{} frame{}: {}", indices.size(), indices.size() == 1 ? "" : "s",
                                           indices.size() == 1 ? "index " + indices.front() : join(indices, ", "))});
  } else {
    add("frames", frames);
  }
  add("repetitions", member(report.experiment, "repetitions"));
  // Which build of each plugin the runs measured (methods/plugins.h): its hash is in their keys.
  if (const json& plugins = member(report.experiment, "plugins"); plugins.is_array() && !plugins.empty()) {
    std::vector<std::string> builds;
    for (const json& plugin : plugins)
      builds.push_back(fmt::format("{} {} (xxhash {}, {})", string_member(plugin, "name"), string_member(plugin, "version"),
                                   string_member(plugin, "hash"), string_member(plugin, "path")));
    facts.push_back({"plugins", join(builds, "; ")});
  }
  if (report.seeds > 1)
    facts.push_back({"seeds", fmt::format("{} (a stochastic run's metrics are the means over {} seeds, its own and the "
                                          "next, \u00b1 their 95 % Student-t interval; a deterministic run is measured "
                                          "once, \u00b1 0; \u2248: not separated from the best, the intervals overlap)",
                                          report.seeds, report.seeds)});
  {
    // Which quantity the methods were measured at (docs/metrics.md, "pixel_samples").
    const nlohmann::json& samples = member(report.experiment, "pixel_samples");
    int count = samples.is_number_integer() ? samples.get<int>() : 1;
    facts.push_back({"pixel samples", count == 1 ? std::string("1 (each method at the pixel centre, against the reference's "
                                                                "footprint average)")
                                                 : fmt::format("{} (each method averaged over a stratified {}-point grid "
                                                               "per pixel; render times include every point)",
                                                               count, count)});
  }
  facts.push_back({"primary metric", report.primary + " (" + direction_text(report.primary) + ")"});
  if (!report.multi()) {
    if (!report.variants.front().reference_key.empty())
      facts.push_back({"reference", reference_text(report.variants.front())});
    return facts;
  }
  // Several variants: each with its resolution, overrides and reference.
  for (const Variant& variant : report.variants) {
    std::vector<std::string> parts;
    if (!resolution_text(variant.resolution).empty()) parts.push_back(resolution_text(variant.resolution));
    if (variant.overrides.is_object() && !variant.overrides.empty())
      parts.push_back("overrides " + variant.overrides.dump());
    if (!variant.listed) parts.push_back("not listed in experiment.json");
    parts.push_back(variant.reference_key.empty() ? "no reference" : "reference " + reference_text(variant));
    facts.push_back({"variant " + variant.name, join(parts, "; ")});
  }
  return facts;
}

// One-line findings at the top: best, fastest, overall front.
std::vector<std::string> findings(const Report& report, bool html) {
  std::vector<std::string> lines;
  auto name = [&](size_t i) {
    std::string label = report.display(i);
    return html ? "<b>" + html_escape(label) + "</b>" : "**" + md_escape(label) + "**";
  };
  lines.push_back(fmt::format("{} runs: {} ok, {} failed{}{}.", report.runs.size() + report.missing.size(),
                              report.runs.size() - report.failed_count() - report.stale_count(), report.failed_count(),
                              report.stale_count() ? fmt::format(", {} stale", report.stale_count()) : "",
                              report.missing.empty() ? "" : fmt::format(", {} not run yet", report.missing.size())));
  size_t empty = 0;
  for (size_t i : report.ok_runs()) empty += report.runs[i].empty_reference ? 1 : 0;
  if (empty)
    lines.push_back(fmt::format("{} run{} against an empty reference (no caustic in view; the experiment sets "
                                "empty_reference_expected): reported as \"empty reference\", not scored, and left out "
                                "of best values, fronts, claims and plots; timings are still shown.",
                                empty, empty == 1 ? "" : "s"));
  if (!report.claims.empty())
    lines.push_back(claims_count_text(report) + (html ? " See <a href=\"#claims\">Claims</a>." : " See Claims below."));
  // Every text read from the results folder is escaped for the document: experiment.json may be edited.
  const auto text = [&](const std::string& plain) { return html ? html_escape(plain) : md_text(plain); };
  const std::string primary = text(report.primary);
  auto describe = [&](size_t i) {
    auto time = report.runs[i].frame_ms();
    return fmt::format("{} ({}, {} ms)", name(i), text(primary_caption(report, report.runs[i])),
                       time ? num(*time) : "\u2014");
  };
  // One set of lines per variant (best, fastest, front and reference error compare runs of one variant only).
  for (size_t v = 0; v < report.variants.size(); ++v) {
    const Variant& variant = report.variants[v];
    std::string in = report.multi() ? " (variant " + text(variant.name) + ")" : "";
    std::optional<size_t> best, fastest;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].variant_index != v) continue;
      auto value = report.runs[i].metric(report.primary);
      if (finite(value) && (!best || quantity_better(report.primary, *value, *report.runs[*best].metric(report.primary))))
        best = i;
      auto time = report.runs[i].frame_ms();
      if (finite(time) && (!fastest || *time < *report.runs[*fastest].frame_ms())) fastest = i;
    }
    if (best) {
      // The runs whose interval overlaps the best's: the best mean is not told apart from theirs.
      std::vector<std::string> close;
      for (size_t i : report.ok_runs())
        if (i != *best && report.runs[i].variant_index == v && report.runs[i].metric(report.primary) &&
            !separated(report.runs[*best], report.runs[i], report.primary))
          close.push_back(name(i));
      lines.push_back("Best " + primary + in + ": " + describe(*best) +
                      (close.empty() ? "" : "; not separated (95 % intervals overlap) from " + join(close, ", ")) + ".");
    }
    if (fastest) lines.push_back("Fastest frame" + in + ": " + describe(*fastest) + ".");
    const std::vector<size_t>& overall = report.fronts[v].overall;
    if (!overall.empty()) {
      std::vector<std::string> steps;
      for (size_t k = 0; k < overall.size(); ++k)
        steps.push_back(describe(overall[k]) +
                        (k > 0 && !separated(report.runs[overall[k - 1]], report.runs[overall[k]], report.primary)
                             ? " (not separated from the previous: intervals overlap)"
                             : ""));
      lines.push_back("Pareto front over all methods" + in +
                      " (fastest first, \u25c6 in the table): " + join(steps, " \u2192 ") + ".");
    }
    if (best && report.primary == "relmse" && variant.reference_error && *variant.reference_error > 0.0) {
      double value = *report.runs[*best].metric(report.primary);
      double ratio = value / *variant.reference_error;
      lines.push_back(fmt::format("The reference's estimated error{} {} is {} the best relMSE ({}\u00d7 below it).", in,
                                  num(*variant.reference_error), ratio >= 10.0 ? "well below" : "NOT well below",
                                  fmt::format("{:.3g}", ratio)));
    }
    // The reference's caustic light in view by light-path class (the first frame's; issue 52).
    if (std::optional<std::string> required = scene_requirements_text(variant.reference))
      lines.push_back(fmt::format("What this scene requires{} (the reference's caustic light in view, frame {}): {}.", in,
                                  variant.reference.value("frame", 0), text(*required)));
    // Where each run's light went (Run::light_account): what each method does not model, once per
    // method, and every run whose light is not accounted for.
    std::map<std::string, std::string> not_modelled;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].variant_index != v) continue;
      const std::optional<LightAccount>& account = report.runs[i].light_account;
      if (!account) continue;
      if ((account->model >= 0.0005 || account->excess >= 0.0005) && !not_modelled.count(report.runs[i].method)) {
        std::vector<std::string> limits;
        if (account->model >= 0.0005)
          limits.push_back(fmt::format("does not model {:.1f} % of it ({})", 100.0 * account->model,
                                       unmodelled_text(*account)));
        if (account->excess >= 0.0005)
          limits.push_back(fmt::format("may add the {:.1f} % that occluders block (occlusion)", 100.0 * account->excess));
        not_modelled[report.runs[i].method] = report.runs[i].method + " " + join(limits, " and ");
      }
      if (account->flagged)
        lines.push_back(fmt::format("Light not accounted for{}: {} {}.", in, name(i), text(describe_light_account(*account))));
    }
    if (!not_modelled.empty()) {
      std::vector<std::string> parts;
      for (const auto& [method, part] : not_modelled) parts.push_back(text(part));
      lines.push_back(fmt::format("Declared limits{} (the reference's light in view each method declares it does not "
                                  "model): {}.", in, join(parts, "; ")));
    }
  }
  // The baselines (metrics/baselines.h): what showing nothing scores, who does not beat it, and the metrics
  // on which it beats most runs.
  for (size_t v = 0; v < report.variants.size(); ++v) {
    const Variant& variant = report.variants[v];
    const std::optional<double> black = variant.black(report.primary);
    if (!black) continue;
    std::vector<std::string> losers;
    for (size_t i : report.ok_runs())
      if (report.runs[i].variant_index == v && no_better_than_black(report, report.runs[i])) losers.push_back(name(i));
    std::string blurred;
    if (variant.baselines.size() > 1 && variant.baselines[1].values.count(report.primary))
      blurred = fmt::format(", the reference blurred {}", num(variant.baselines[1].values.at(report.primary)));
    lines.push_back(fmt::format("Baselines{}: a black image scores {} {}{}; {}.",
                                report.multi() ? " (variant " + text(variant.name) + ")" : "", primary, num(*black),
                                blurred,
                                losers.empty() ? "every run beats it"
                                               : fmt::format("{} run{} do{} not beat it: {}", losers.size(),
                                                             losers.size() == 1 ? "" : "s", losers.size() == 1 ? "es" : "",
                                                             join(losers, ", "))));
  }
  for (const auto& [metric, count] : black_wins(report)) {
    if (count.scored < 2 || 2 * count.beaten <= count.scored) continue;
    lines.push_back(fmt::format("On {} the black image scores as well as or better than {} of {} runs: that metric does "
                                "not rank these caustics (docs/metrics.md, \"Which metric for which question\").",
                                metric, count.beaten, count.scored));
  }
  // What each frame budget buys (the equal-time view; its table is under "Equal time and equal error").
  for (const std::string& line : budget_lines(report)) lines.push_back(html ? html_escape(line) : md_escape(line));
  return lines;
}

}  // namespace causticbench::report_detail
