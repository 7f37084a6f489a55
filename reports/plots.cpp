// The plots of report.html as Vega-Lite v5 specifications (rendered offline by vega-embed): the
// trade-off of the primary metric against frame time with the Pareto fronts, the reference's
// convergence, and the primary metric against each knob a method sweeps (docs/reports.md, "Plots").
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>

#include "core/errors.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

bool all_positive(const std::vector<double>& values) {
  return !values.empty() && std::all_of(values.begin(), values.end(), [](double v) { return v > 0.0; });
}

json base_spec(const std::string& title, const std::string& subtitle) {
  json title_block = {{"text", title}, {"anchor", "start"}, {"fontSize", 15}};
  if (!subtitle.empty()) title_block["subtitle"] = subtitle;
  return {{"$schema", "https://vega.github.io/schema/vega-lite/v5.json"},
          {"title", title_block},
          {"width", 430},
          {"height", 300},
          {"config",
           {{"font", "system-ui, -apple-system, Segoe UI, Helvetica, Arial, sans-serif"},
            {"axis", {{"labelFontSize", 11}, {"titleFontSize", 12}, {"gridOpacity", 0.6}}},
            {"legend", {{"labelLimit", 360}, {"labelFontSize", 11}, {"titleFontSize", 12}}},
            {"title", {{"subtitleColor", "#555"}, {"subtitleFontSize", 11}}}}}};
}

json axis(const std::string& field, const std::string& title, bool log) {
  json encoding = {{"field", field}, {"type", "quantitative"}, {"title", title}};
  if (log) {
    encoding["scale"] = {{"type", "log"}};
    encoding["axis"] = {{"format", "~g"}};
  } else {
    encoding["scale"] = {{"zero", false}};
  }
  return encoding;
}

// Vega's tableau10 colours, given to the methods in their order, so that a method keeps its colour in
// every plot even when a plot shows only some of the methods.
json method_colour(const Report& report, const std::set<std::string>& shown = {}) {
  static const char* const palette[] = {"#4c78a8", "#f58518", "#e45756", "#72b7b2", "#54a24b",
                                        "#eeca3b", "#b279a2", "#ff9da6", "#9d755d", "#bab0ac"};
  json domain = json::array(), range = json::array();
  for (size_t m = 0; m < report.methods.size(); ++m) {
    if (!shown.empty() && !shown.count(report.methods[m])) continue;
    domain.push_back(report.methods[m]);
    range.push_back(palette[m % 10]);
  }
  return {
      {"field", "method"}, {"type", "nominal"}, {"title", "method"}, {"scale", {{"domain", domain}, {"range", range}}}};
}

// A dashed horizontal rule at `value` with a label, as two layers.
std::vector<json> rule_layers(const std::string& field, double value, const std::string& text,
                              const std::string& colour) {
  json data = {{"values", json::array({{{field, value}, {"text", text}}})}};
  json y = {{"field", field}, {"type", "quantitative"}};
  return {{{"data", data},
           {"mark", {{"type", "rule"}, {"strokeDash", {6, 4}}, {"color", colour}, {"strokeWidth", 1.5}}},
           {"encoding", {{"y", y}}}},
          {{"data", data},
           {"mark",
            {{"type", "text"},
             {"align", "left"},
             {"baseline", "bottom"},
             {"dx", 4},
             {"dy", -3},
             {"color", colour},
             {"fontSize", 11}}},
           {"encoding", {{"y", y}, {"x", {{"value", 0}}}, {"text", {{"field", "text"}}}}}}};
}

json run_row(const Report& report, size_t i) {
  const Run& run = report.runs[i];
  json row = {{"key", run.key},
              {"method", run.method},
              {"label", report.display(i)},
              {"knobs", run.swept_text()},
              {"frame_ms", run.frame_ms().value_or(NAN)},
              {"value", run.metric(report.primary).value_or(NAN)},
              {"front", report.on_front(i)}};
  if (report.multi()) {
    row["variant"] = run.variant;
    row["series"] = run.variant + " " + run.method;
  }
  return row;
}

json tooltip(const Report& report) {
  json fields = json::array({{{"field", "label"}, {"title", "run"}},
                             {{"field", "method"}},
                             {{"field", "knobs"}, {"title", "swept"}},
                             {{"field", "frame_ms"}, {"title", "frame ms (median)"}, {"format", ".4g"}},
                             {{"field", "value"}, {"title", report.primary}, {"format", ".4g"}}});
  if (report.multi()) fields.insert(fields.begin() + 2, json{{"field", "variant"}});
  return fields;
}

// The reference noise floor rules of the error plots (primary metric relMSE only): one per variant whose
// reference has a positive floor, labelled with the variant's name when there are several. The floors
// are appended to `values` (for the choice of a log axis).
std::vector<json> floor_layers(const Report& report, const std::string& field, std::vector<double>& values) {
  std::vector<json> layers;
  if (report.primary != "relmse") return layers;
  for (const Variant& variant : report.variants) {
    if (!finite(variant.noise_floor) || !(*variant.noise_floor > 0.0)) continue;
    double floor = *variant.noise_floor;
    values.push_back(floor);
    std::string text = report.multi() ? fmt::format("reference noise floor {} {}", variant.name, num(floor))
                                      : "reference noise floor " + num(floor);
    for (json& layer : rule_layers(field, floor, text, "#666")) layers.push_back(layer);
  }
  return layers;
}

// Points of several variants are told apart by their shape.
void add_variant_shape(const Report& report, json& encoding) {
  if (!report.multi()) return;
  json names = json::array();
  for (const Variant& variant : report.variants) names.push_back(variant.name);
  encoding["shape"] = {{"field", "variant"}, {"type", "nominal"}, {"title", "variant"}, {"scale", {{"domain", names}}}};
}

void make_tradeoff_plot(Report& report) {
  std::vector<size_t> plotted;
  std::vector<double> times, values;
  for (size_t i : report.ok_runs()) {
    auto time = report.runs[i].frame_ms();
    auto value = report.runs[i].metric(report.primary);
    if (!finite(time) || !finite(value)) continue;
    plotted.push_back(i);
    times.push_back(*time);
    values.push_back(*value);
  }
  if (plotted.empty()) return;
  std::vector<json> floors = floor_layers(report, "value", values);
  bool log_x = all_positive(times), log_y = all_positive(values);

  // Fronts are computed within each variant: one line per (variant, method), one band per variant.
  json front_points = json::array(), dominated = json::array(), front_lines = json::array(), overall = json::array();
  for (size_t i : plotted) (report.on_front(i) ? front_points : dominated).push_back(run_row(report, i));
  for (const Fronts& fronts : report.fronts) {
    for (const auto& [method, front] : fronts.per_method) {
      int order = 0;
      for (size_t i : front) {
        json row = run_row(report, i);
        row["order"] = order++;
        front_lines.push_back(row);
      }
    }
    if (fronts.overall.size() < 2) continue;
    int order = 0;
    for (size_t i : fronts.overall) {
      json row = run_row(report, i);
      row["order"] = order++;
      overall.push_back(row);
    }
  }

  std::string y_title = fmt::format("{} ({}{})", report.primary, direction_text(report.primary), log_y ? ", log" : "");
  json x = axis("frame_ms", std::string("frame time, median ms") + (log_x ? " (log)" : ""), log_x);
  json y = axis("value", y_title, log_y);
  json layers = json::array();
  if (!overall.empty()) {
    json band = {{"x", x}, {"y", y}, {"order", {{"field", "order"}}}};
    if (report.multi()) band["detail"] = {{"field", "variant"}};
    layers.push_back({{"data", {{"values", overall}}},
                      {"mark",
                       {{"type", "line"},
                        {"color", "#999"},
                        {"opacity", 0.3},
                        {"strokeWidth", 9},
                        {"strokeCap", "round"},
                        {"strokeJoin", "round"}}},
                      {"encoding", band}});
  }
  json lines = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"order", {{"field", "order"}}}};
  if (report.multi()) lines["detail"] = {{"field", "series"}};
  layers.push_back(
      {{"data", {{"values", front_lines}}}, {"mark", {{"type", "line"}, {"strokeWidth", 2}}}, {"encoding", lines}});
  json points = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"tooltip", tooltip(report)}};
  add_variant_shape(report, points);
  if (!dominated.empty()) {
    layers.push_back({{"data", {{"values", dominated}}},
                      {"mark", {{"type", "point"}, {"filled", false}, {"size", 60}, {"strokeWidth", 1.5}}},
                      {"encoding", points}});
  }
  layers.push_back({{"data", {{"values", front_points}}},
                    {"mark", {{"type", "point"}, {"filled", true}, {"size", 80}, {"opacity", 1}}},
                    {"encoding", points}});
  for (json& layer : floors) layers.push_back(layer);
  json spec = base_spec(fmt::format("Trade-off: {} versus frame time", report.primary),
                        report.multi() ? "each point one run, shape = scene variant; filled = on its method's Pareto "
                                         "front within its variant, hollow = dominated; grey bands = fronts over all "
                                         "methods"
                                       : "each point one run; filled = on its method's Pareto front, hollow = "
                                         "dominated; grey band = front over all methods");
  spec["layer"] = layers;
  std::string caption = fmt::format(
      "x: median frame time (update + render) over the repetitions; y: {} against the reference (mean over the "
      "frames). A run is on its method's front when no run of that method is at least as fast and at least as "
      "good ({}) and strictly better in one of the two.",
      report.primary, direction_text(report.primary));
  if (report.multi())
    caption +=
        " Fronts are computed within each scene variant: a run competes only with runs of its own variant, each "
        "measured against its own reference.";
  if (!floors.empty())
    caption += report.multi() ? " Below a variant's dashed noise floor its reference cannot tell errors apart."
                              : " Below the dashed noise floor the reference cannot tell errors apart.";
  report.plots.push_back({"plot-tradeoff", caption, spec});
}

void make_convergence_plot(Report& report) {
  // One line per variant's reference (a plain experiment has one).
  json rows = json::array();
  std::vector<double> seconds, floors;
  for (const Variant& variant : report.variants) {
    for (const json& entry : variant.history) {
      auto s = number(entry, "seconds"), f = number(entry, "noise_floor");
      if (!finite(s) || !finite(f)) continue;
      json row = {{"seconds", *s}, {"noise_floor", *f}};
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
    if (!best || better("relmse", *value, *best)) {
      best = *value;
      best_label = report.display(i);
    }
  }
  std::vector<double> all = floors;
  if (best) all.push_back(*best);
  bool log_x = all_positive(seconds), log_y = all_positive(all);
  json x = axis("seconds", std::string("reference time, s") + (log_x ? " (log)" : ""), log_x);
  json y = axis("noise_floor", std::string("noise floor, estimated relMSE") + (log_y ? " (log)" : ""), log_y);
  json tip = json::array({{{"field", "pass"}},
                          {{"field", "photons"}, {"format", ",d"}},
                          {{"field", "seconds"}, {"format", ".4g"}},
                          {{"field", "noise_floor"}, {"title", "noise floor"}, {"format", ".4g"}}});
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
         rule_layers("noise_floor", *best, "best method relMSE " + num(*best) + " (" + best_label + ")", "#e45756"))
      layers.push_back(layer);
  }
  json spec = base_spec("Reference convergence: noise floor versus time",
                        "relMSE of the reference estimated from two independent halves, after each pass");
  spec["layer"] = layers;
  std::string caption =
      "The reference's estimated relMSE (its noise floor) after each progressive pass, against the seconds it "
      "had run. Metrics below the floor are not resolved; the red rule is the best relMSE any method reached "
      "in this experiment.";
  if (report.multi()) caption += " One line per scene variant's reference; the rule is the best over all variants.";
  report.plots.push_back({"plot-convergence", caption, spec});
}

void make_sweep_plots(Report& report) {
  // Knob name -> methods that sweep it over at least two values.
  std::map<std::string, std::set<std::string>> knobs;
  for (const std::string& method : report.methods) {
    std::map<std::string, std::set<std::string>> seen;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].method != method || !report.runs[i].swept().is_object()) continue;
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
      if (!methods.count(run.method) || !run.swept().contains(knob) || !finite(run.metric(report.primary))) continue;
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
    // A line holds the runs of one method whose other knobs are all equal: swept ones, and fixed ones
    // that differ between its entries (pinhole with and without filtering), and the variant.
    std::map<std::string, std::set<std::string>> varying;  // method -> knobs other than `knob` that vary
    {
      std::map<std::string, std::map<std::string, std::set<std::string>>> seen;
      for (size_t i : runs) {
        const json knobs = run_knobs(report.runs[i]);  // named: items() would outlive a temporary
        for (const auto& [name, value] : knobs.items()) {
          // receiver_pixels follows the variant: not a knob of its own.
          if (name != knob && name != "receiver_pixels") seen[report.runs[i].method][name].insert(value.dump());
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
      for (const std::string& name : varying[run.method])
        others[name] = knobs.contains(name) ? knobs[name] : json("\u2014");
      std::string others_text = knobs_text(others);
      if (others_text.empty()) others_text = "\u2014";
      others_seen.insert(run.method + "|" + others_text);
      json row = run_row(report, i);
      row["x"] = numeric ? value_of(run) : json(value_text(value_of(run)));
      row["others"] = others_text;
      row["series"] = run.method + " " + others_text;
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
  make_tradeoff_plot(report);
  make_convergence_plot(report);
  make_sweep_plots(report);
}

}  // namespace causticbench::report_detail
