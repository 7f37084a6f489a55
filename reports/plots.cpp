// The plots of report.html as Vega-Lite v5 specifications (rendered offline by vega-embed): the
// trade-offs (tradeoff_plots.cpp), the reference's convergence, and the primary metric against each
// knob a method sweeps (docs/reports.md, "Plots"); the pieces they share: plot_specs.h.
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>

#include "core/errors.h"
#include "methods/registry.h"
#include "reports/plot_specs.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

void make_convergence_plot(Report& report) {
  // One line per variant's reference (a plain experiment has one).
  json rows = json::array();
  std::vector<double> seconds, floors;
  for (const Variant& variant : report.variants) {
    for (const json& entry : variant.history) {
      auto s = number(entry, "seconds"), f = number(entry, "error_estimate");
      if (!finite(s) || !finite(f)) continue;
      json row = {{"seconds", *s}, {"error_estimate", *f}};
      if (entry.contains("pass")) row["pass"] = entry["pass"];
      if (entry.contains("photons")) row["photons"] = entry["photons"];
      if (report.multi()) row["variant"] = variant.name;
      rows.push_back(row);
      seconds.push_back(*s);
      floors.push_back(*f);
    }
  }
  if (rows.empty()) return;
  // The best relMSE any method reached: the floor must sit well below it.
  std::optional<double> best;
  std::string best_label;
  for (size_t i : report.ok_runs()) {
    auto value = report.runs[i].metric("relmse");
    if (!finite(value)) continue;
    if (!best || quantity_better("relmse", *value, *best)) {
      best = *value;
      best_label = report.display(i);
    }
  }
  std::vector<double> all = floors;
  if (best) all.push_back(*best);
  bool log_x = all_positive(seconds), log_y = all_positive(all);
  json x = axis("seconds", std::string("reference time, s") + (log_x ? " (log)" : ""), log_x);
  json y = axis("error_estimate", std::string("reference error, estimated relMSE") + (log_y ? " (log)" : ""), log_y);
  json tip = json::array({{{"field", "pass"}},
                          {{"field", "photons"}, {"format", ",d"}},
                          {{"field", "seconds"}, {"format", ".4g"}},
                          {{"field", "error_estimate"}, {"title", "reference error"}, {"format", ".4g"}}});
  json layers = json::array();
  if (report.multi()) {
    tip.insert(tip.begin(), json{{"field", "variant"}});
    layers.push_back({{"data", {{"values", rows}}},
                      {"mark", {{"type", "line"}, {"point", {{"filled", true}, {"size", 30}}}}},
                      {"encoding",
                       {{"x", x},
                        {"y", y},
                        {"color", {{"field", "variant"}, {"type", "nominal"}, {"title", "variant"}, {"sort", nullptr}}},
                        {"tooltip", tip}}}});
  } else {
    layers.push_back(
        {{"data", {{"values", rows}}},
         {"mark",
          {{"type", "line"}, {"point", {{"filled", true}, {"size", 30}, {"color", "#333"}}}, {"color", "#333"}}},
         {"encoding", {{"x", x}, {"y", y}, {"tooltip", tip}}}});
  }
  if (best) {
    for (json& layer :
         rule_layers("error_estimate", *best, "best method relMSE " + num(*best) + " (" + best_label + ")", "#e45756"))
      layers.push_back(layer);
  }
  json spec = base_spec("Reference convergence: reference error versus time",
                        "the reference's estimate of its own total error (variance plus bias), after each pass");
  spec["layer"] = layers;
  std::string caption =
      "The reference's estimate of its own total error (relMSE against the pixels' true E_c: variance, plus "
      "the estimated squared bias where its estimator has one) after each pass, against the seconds it had run. "
      "A method's error below it is not resolved; the red rule is the best relMSE any method reached in this "
      "experiment.";
  if (report.multi()) caption += " One line per scene variant's reference; the rule is the best over all variants.";
  report.plots.push_back({"plot-convergence", caption, spec});
}

// Error against time (docs/reports.md, "Error against time"): the runs of every method that sweep its
// budget knob (MethodInfo::budget_knob: photons, samples, passes), their relMSE against their time to a
// first frame (precomputation plus the median frame), on log axes, one line per method and setting of
// its other knobs; the reference's own convergence (its estimated relMSE after each pass against its
// seconds) joins them, as renderer papers draw it. Only with relMSE: the reference estimates no other.
void make_error_time_plot(Report& report) {
  const std::string metric = "relmse";
  const json& measured = member(report.experiment, "metrics");
  if (!measured.is_array() || std::find(measured.begin(), measured.end(), json(metric)) == measured.end()) return;
  json rows = json::array();
  std::vector<double> xs, ys;
  std::map<std::string, size_t> points_per_series;
  bool banded = false;
  for (size_t i : report.ok_runs()) {
    const Run& run = report.runs[i];
    std::string knob;
    try {
      knob = find_method(run.method).info().budget_knob;
    } catch (const std::exception&) {
      continue;  // a method this build does not register
    }
    if (knob.empty() || !run.swept().is_object() || !run.swept().contains(knob)) continue;
    const auto error = run.metric(metric);
    const auto frame_ms = run.frame_ms();
    if (!finite(error) || !finite(frame_ms)) continue;
    const double seconds = run.record.prepare.prepare_seconds + *frame_ms / 1000.0;
    json others = run.swept();
    others.erase(knob);
    std::string others_text = knobs_text(others);
    json row = run_row(report, i);
    row["seconds"] = seconds;
    row["error"] = *error;
    row["budget"] = knob + "=" + value_text(run.swept()[knob]);
    row["series"] = (report.multi() ? run.variant + " " : std::string()) + run.entry +
                    (others_text.empty() ? "" : " " + others_text);
    // The seed band: the 95 % interval of the mean over the seeds (its low end kept above zero for the
    // log axis: a band that reaches zero is drawn down to a hundredth of the mean).
    if (const std::optional<MetricInterval> interval = run.interval(metric); interval && interval->count > 1) {
      row["low"] = std::max(interval->low(), 0.01 * *error);
      row["high"] = interval->high();
      row["interval"] = "\u00b1 " + num(interval->half_width) + fmt::format(" over {} seeds", interval->count);
      banded = true;
    }
    ++points_per_series[row["series"].get<std::string>()];
    rows.push_back(row);
    xs.push_back(seconds);
    ys.push_back(*error);
  }
  size_t lines = 0;
  for (const auto& [series, count] : points_per_series) lines += count >= 2;
  if (lines == 0) return;
  json reference_rows = json::array();
  for (const Variant& variant : report.variants)
    for (const json& entry : variant.history) {
      auto s = number(entry, "seconds"), f = number(entry, "error_estimate");
      if (!finite(s) || !finite(f)) continue;
      reference_rows.push_back({{"seconds", *s}, {"error", *f}, {"series", (report.multi() ? variant.name + " " : std::string()) + "reference"}});
      xs.push_back(*s);
      ys.push_back(*f);
    }
  const bool log_x = all_positive(xs), log_y = all_positive(ys);
  json x = axis("seconds", std::string("time to a first frame, s") + (log_x ? " (log)" : ""), log_x);
  json y = axis("error", std::string("relMSE") + (log_y ? " (log)" : ""), log_y);
  json tip = tooltip(report);
  tip.push_back({{"field", "budget"}});
  tip.push_back({{"field", "seconds"}, {"title", "time to a first frame, s"}, {"format", ".4g"}});
  if (banded) tip.push_back({{"field", "interval"}, {"title", "95 % interval"}});
  json layers = json::array();
  if (banded) {
    json low = y, high = {{"field", "high"}};
    low["field"] = "low";
    layers.push_back({{"data", {{"values", rows}}},
                      {"transform", json::array({{{"filter", "isValid(datum.low)"}}})},
                      {"mark", {{"type", "area"}, {"opacity", 0.2}}},
                      {"encoding",
                       {{"x", x}, {"y", low}, {"y2", high}, {"color", method_colour(report)},
                        {"detail", {{"field", "series"}}}, {"order", {{"field", "seconds"}}}}}});
  }
  layers.push_back({{"data", {{"values", rows}}},
                    {"mark", {{"type", "line"}, {"point", {{"filled", true}, {"size", 40}}}}},
                    {"encoding",
                     {{"x", x},
                      {"y", y},
                      {"color", method_colour(report)},
                      {"detail", {{"field", "series"}}},
                      {"order", {{"field", "seconds"}}},
                      {"tooltip", tip}}}});
  if (!reference_rows.empty()) {
    json reference_tip = json::array({{{"field", "series"}, {"title", "curve"}},
                                      {{"field", "seconds"}, {"format", ".4g"}},
                                      {{"field", "error"}, {"title", "estimated relMSE"}, {"format", ".4g"}}});
    layers.push_back({{"data", {{"values", reference_rows}}},
                      {"mark", {{"type", "line"}, {"strokeDash", {4, 3}}, {"color", "#333"}, {"point", {{"color", "#333"}}}}},
                      {"encoding", {{"x", x}, {"y", y}, {"detail", {{"field", "series"}}}, {"tooltip", reference_tip}}}});
  }
  json spec = base_spec("relMSE against time", "the runs that sweep their method's budget knob, and the reference's own");
  spec["layer"] = layers;
  report.plots.push_back(
      {"plot-error-time",
       "Each method that buys accuracy with time (photons, samples, passes: the budget knob its declaration names) "
       "along its sweep of that knob: relMSE against its time to a first frame (precomputation plus the median "
       "frame), one line per method and setting of its other knobs. The dashed curve is the reference's estimate "
       "of its own relMSE after each pass against its seconds: below it, a run's error is not resolved." +
           std::string(banded ? " Shaded: the 95 % interval of the mean over the seeds." : ""),
       spec});
}

void make_sweep_plots(Report& report) {
  // Knob name -> entries that sweep it over at least two values.
  std::map<std::string, std::set<std::string>> knobs;
  for (const std::string& method : report.entries) {
    std::map<std::string, std::set<std::string>> seen;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].entry != method || !report.runs[i].swept().is_object()) continue;
      for (const auto& [name, value] : report.runs[i].swept().items()) seen[name].insert(value.dump());
    }
    for (const auto& [name, values] : seen)
      if (values.size() >= 2) knobs[name].insert(method);
  }
  for (const auto& [knob, methods] : knobs) {
    std::vector<size_t> runs;
    bool numeric = true;
    std::vector<double> xs, values;
    // The knob's value as resolved (typed) in the record, not the swept text ("300" would sort after
    // "10000"): numbers make a numeric, ordered axis.
    auto value_of = [&](const Run& run) {
      json knobs = run_knobs(run);
      return knobs.contains(knob) ? knobs[knob] : run.swept()[knob];
    };
    for (size_t i : report.ok_runs()) {
      const Run& run = report.runs[i];
      if (!methods.count(run.entry) || !run.swept().contains(knob) || !finite(run.metric(report.primary))) continue;
      runs.push_back(i);
      const json x = value_of(run);
      if (x.is_number())
        xs.push_back(x.get<double>());
      else
        numeric = false;
      values.push_back(*run.metric(report.primary));
    }
    if (runs.size() < 2) continue;
    std::vector<json> floors = floor_layers(report, "value", values);
    bool log_x = false;
    if (numeric) {
      auto [low, high] = std::minmax_element(xs.begin(), xs.end());
      log_x = *low > 0.0 && *high / *low >= 20.0;
    }
    bool log_y = all_positive(values);
    // A line holds the runs of one entry whose other knobs are all equal: swept ones, and fixed ones
    // that differ between its entries (pinhole with and without filtering), and the variant.
    std::map<std::string, std::set<std::string>> varying;  // method -> knobs other than `knob` that vary
    {
      std::map<std::string, std::map<std::string, std::set<std::string>>> seen;
      for (size_t i : runs) {
        const json knobs = run_knobs(report.runs[i]);  // named: items() would outlive a temporary
        for (const auto& [name, value] : knobs.items()) {
          // receiver_pixels follows the variant: not a knob of its own.
          if (name != knob && name != "receiver_pixels") seen[report.runs[i].entry][name].insert(value.dump());
        }
      }
      for (const auto& [method, by_knob] : seen)
        for (const auto& [name, texts] : by_knob)
          if (texts.size() > 1) varying[method].insert(name);
    }
    json rows = json::array();
    std::set<std::string> others_seen;
    for (size_t i : runs) {
      const Run& run = report.runs[i];
      json others = json::object();
      const json knobs = run_knobs(run);
      for (const std::string& name : varying[run.entry])
        others[name] = knobs.contains(name) ? knobs[name] : json("\u2014");
      std::string others_text = knobs_text(others);
      if (others_text.empty()) others_text = "\u2014";
      others_seen.insert(run.entry + "|" + others_text);
      json row = run_row(report, i);
      row["x"] = numeric ? value_of(run) : json(value_text(value_of(run)));
      row["others"] = others_text;
      row["series"] = run.entry + " " + others_text;
      rows.push_back(row);
    }
    json x = numeric ? axis("x", knob + (log_x ? " (log)" : ""), log_x)
                     : json{{"field", "x"}, {"type", "ordinal"}, {"title", knob}, {"sort", nullptr}};
    json y = axis(
        "value", fmt::format("{} ({}{})", report.primary, direction_text(report.primary), log_y ? ", log" : ""), log_y);
    bool dashed = others_seen.size() > methods.size();
    json line_encoding = {{"x", x},
                          {"y", y},
                          {"color", method_colour(report, methods)},
                          {"detail", {{"field", "series"}}},
                          {"order", {{"field", "x"}}}};
    if (dashed) line_encoding["strokeDash"] = {{"field", "others"}, {"type", "nominal"}, {"title", "other knobs"}};
    json layers = json::array();
    layers.push_back(
        {{"data", {{"values", rows}}}, {"mark", {{"type", "line"}, {"strokeWidth", 2}}}, {"encoding", line_encoding}});
    json tip = tooltip(report);
    tip.push_back({{"field", "others"}, {"title", "other knobs"}});
    layers.push_back({{"data", {{"values", rows}}},
                      {"mark", {{"type", "point"}, {"filled", true}, {"size", 50}}},
                      {"encoding", {{"x", x}, {"y", y}, {"color", method_colour(report, methods)}, {"tooltip", tip}}}});
    for (json& layer : floors) layers.push_back(layer);
    std::vector<std::string> method_list(methods.begin(), methods.end());
    json spec = base_spec(fmt::format("{} versus {}", report.primary, knob),
                          fmt::format("swept by {}; one line per method{}", join(method_list, ", "),
                                      dashed ? " and combination of its other knobs (dash)" : ""));
    spec["layer"] = layers;
    report.plots.push_back({"plot-sweep-" + file_safe(knob),
                            fmt::format("The primary metric of every run that sweeps {}, against its value; the "
                                        "other knobs of a line are equal (swept or fixed, as its dash says).",
                                        knob),
                            spec});
  }
}

}  // namespace

void make_plots(Report& report) {
  make_tradeoff_plots(report);
  make_convergence_plot(report);
  make_error_time_plot(report);
  make_sweep_plots(report);
}

}  // namespace causticbench::report_detail
