// The trade-off plots of report.html (docs/reports.md, "Plots"): one per trade-off the experiment names
// (default: the primary metric against frame time), each with its Pareto fronts per method and over all
// methods within each variant, and the total cost over N frames (prepare + N x frame time) against the
// primary metric, one panel per frame count, where a precomputing method's break-even shows as the panel
// in which its points move left of the others.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/errors.h"
#include "reports/plot_specs.h"
#include "reports/report.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

std::string axis_title(const std::string& name, bool log) {
  std::optional<QuantityInfo> quantity = find_quantity(name);
  std::string title = quantity ? quantity_title(*quantity) : name;
  return log ? title + " (log)" : title;
}

json tradeoff_tooltip(const Report& report, const std::string& x, const std::string& y) {
  json fields = json::array({{{"field", "label"}, {"title", "run"}},
                             {{"field", "method"}},
                             {{"field", "knobs"}, {"title", "swept"}},
                             {{"field", "x"}, {"title", x}, {"format", ".4g"}},
                             {{"field", "y"}, {"title", y}, {"format", ".4g"}}});
  if (report.multi()) fields.insert(fields.begin() + 2, json{{"field", "variant"}});
  return fields;
}

// The layers of one front plot: grey bands for the fronts over all methods, a line per method's front,
// hollow dominated points and filled front points; `lines` and `bands` list the front rows in order.
json front_layers(const Report& report, const json& x, const json& y, const json& tip, const json& dominated,
                  const json& front_points, const json& lines, const json& bands) {
  json layers = json::array();
  if (!bands.empty()) {
    json band = {{"x", x}, {"y", y}, {"order", {{"field", "order"}}}, {"detail", {{"field", "band"}}}};
    layers.push_back({{"data", {{"values", bands}}},
                      {"mark",
                       {{"type", "line"},
                        {"color", "#999"},
                        {"opacity", 0.3},
                        {"strokeWidth", 9},
                        {"strokeCap", "round"},
                        {"strokeJoin", "round"}}},
                      {"encoding", band}});
  }
  json line = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"order", {{"field", "order"}}},
               {"detail", {{"field", "series"}}}};
  layers.push_back({{"data", {{"values", lines}}}, {"mark", {{"type", "line"}, {"strokeWidth", 2}}}, {"encoding", line}});
  json points = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"tooltip", tip}};
  add_variant_shape(report, points);
  if (!dominated.empty()) {
    layers.push_back({{"data", {{"values", dominated}}},
                      {"mark", {{"type", "point"}, {"filled", false}, {"size", 60}, {"strokeWidth", 1.5}}},
                      {"encoding", points}});
  }
  layers.push_back({{"data", {{"values", front_points}}},
                    {"mark", {{"type", "point"}, {"filled", true}, {"size", 80}, {"opacity", 1}}},
                    {"encoding", points}});
  return layers;
}

// Front rows in order: one series per (variant, method), one band per variant.
void add_front_rows(const Report& report, const std::vector<Fronts>& fronts, const std::function<json(size_t)>& row_of,
                    json& lines, json& bands) {
  for (size_t v = 0; v < fronts.size(); ++v) {
    for (const auto& [method, front] : fronts[v].per_method) {
      int order = 0;
      for (size_t i : front) {
        json row = row_of(i);
        row["order"] = order++;
        row["series"] = report.variants[v].name + " " + method;
        lines.push_back(row);
      }
    }
    if (fronts[v].overall.size() < 2) continue;
    int order = 0;
    for (size_t i : fronts[v].overall) {
      json row = row_of(i);
      row["order"] = order++;
      row["band"] = report.variants[v].name;
      bands.push_back(row);
    }
  }
}

bool on_method_front(const std::vector<Fronts>& fronts, const Run& run, size_t i) {
  const auto& per_method = fronts.at(run.variant_index).per_method;
  auto found = per_method.find(run.entry);
  return found != per_method.end() && std::count(found->second.begin(), found->second.end(), i);
}

void make_tradeoff_plot(Report& report, const Tradeoff& tradeoff, bool first) {
  std::vector<double> xs, ys;
  json front_points = json::array(), dominated = json::array(), lines = json::array(), bands = json::array();
  auto row_of = [&](size_t i) {
    json row = run_row(report, i);
    row["x"] = report.runs[i].quantity(tradeoff.x).value_or(NAN);
    row["y"] = report.runs[i].quantity(tradeoff.y).value_or(NAN);
    return row;
  };
  for (size_t i : report.ok_runs()) {
    auto x = report.runs[i].quantity(tradeoff.x), y = report.runs[i].quantity(tradeoff.y);
    if (!finite(x) || !finite(y)) continue;
    xs.push_back(*x);
    ys.push_back(*y);
    (on_method_front(tradeoff.fronts, report.runs[i], i) ? front_points : dominated).push_back(row_of(i));
  }
  if (xs.empty()) return;
  std::vector<json> floors = tradeoff.y == report.primary ? floor_layers(report, "y", ys) : std::vector<json>{};
  // What a black image and the blurred reference score on y: a run above the black line shows nothing y sees.
  const std::vector<BaselineRule> baselines = baseline_rules(report, tradeoff.y);
  for (const BaselineRule& rule : baselines)
    if (rule.value > 0.0) ys.push_back(rule.value);
  bool log_x = all_positive(xs), log_y = all_positive(ys);
  add_front_rows(report, tradeoff.fronts, row_of, lines, bands);
  json x = axis("x", axis_title(tradeoff.x, log_x), log_x), y = axis("y", axis_title(tradeoff.y, log_y), log_y);
  json layers = front_layers(report, x, y, tradeoff_tooltip(report, tradeoff.x, tradeoff.y), dominated, front_points,
                             lines, bands);
  for (json& layer : floors) layers.push_back(layer);
  for (json& layer : baseline_layers(baselines, "y", log_y)) layers.push_back(layer);
  json spec = base_spec(fmt::format("Trade-off: {} versus {}", tradeoff.y, tradeoff.x),
                        report.multi() ? "each point one run, shape = scene variant; filled = on its method's Pareto "
                                         "front within its variant, hollow = dominated; grey bands = fronts over all "
                                         "methods"
                                       : "each point one run; filled = on its method's Pareto front, hollow = "
                                         "dominated; grey band = front over all methods");
  spec["layer"] = layers;
  std::optional<QuantityInfo> xq = find_quantity(tradeoff.x), yq = find_quantity(tradeoff.y);
  std::string caption = fmt::format(
      "x: {} ({}); y: {} ({}). A run is on its method's front when no run of that method is at least as good on "
      "both axes and strictly better on one.",
      tradeoff.x, xq ? xq->definition : "?", tradeoff.y, yq ? yq->definition : "?");
  if (report.multi())
    caption += " Fronts are computed within each scene variant: a run competes only with runs of its own variant.";
  if (!floors.empty()) caption += " Below the dashed reference error the reference cannot tell errors apart.";
  if (!baselines.empty())
    caption += " The dashed black line is what a black image scores on y, the amber one the reference blurred "
               "(docs/metrics.md, \"Baselines\"): a run no better than the black line shows nothing y can see.";
  std::string id = first && tradeoff.x == "frame_ms" && tradeoff.y == report.primary
                       ? "plot-tradeoff"
                       : "plot-tradeoff-" + file_safe(tradeoff.x) + "-" + file_safe(tradeoff.y);
  report.plots.push_back({id, caption, spec});
}

// A frame count as a person writes it: 216000, not 2.16e+05.
std::string count_text(double count) {
  return count == std::floor(count) && count < 1e15 ? fmt::format("{:.0f}", count) : num(count);
}

std::string frame_counts_text(const std::vector<double>& counts) {
  std::vector<std::string> texts;
  for (double count : counts) texts.push_back(count_text(count));
  return join(texts, ", ");
}

// Total cost in seconds over N frames: prepare + N x frame time.
double total_seconds(const Run& run, double frames) {
  return run.quantity("prepare_seconds").value_or(0.0) + frames * run.frame_ms().value_or(NAN) / 1000.0;
}

void make_total_cost_plot(Report& report) {
  bool any_prepare = false;
  std::vector<size_t> runs;
  for (size_t i : report.ok_runs()) {
    const Run& run = report.runs[i];
    if (!finite(run.frame_ms()) || !finite(run.metric(report.primary))) continue;
    runs.push_back(i);
    if (run.quantity("prepare_seconds").value_or(0.0) > 0.0) any_prepare = true;
  }
  if (runs.empty() || !any_prepare || report.total_cost_frames.empty()) return;
  json points = json::array(), lines = json::array();
  std::vector<double> ys;
  auto better_y = [&](double a, double b) { return quantity_better(report.primary, a, b); };
  for (double frames : report.total_cost_frames) {
    const std::string panel = fmt::format("N = {} frames", count_text(frames));
    // Each method's front on (total cost, error) within each variant, in this panel.
    std::map<std::pair<size_t, std::string>, std::vector<size_t>> groups;
    for (size_t i : runs) groups[{report.runs[i].variant_index, report.runs[i].entry}].push_back(i);
    for (const auto& [group, members] : groups) {
      std::vector<TradeoffPoint> plane;
      for (size_t i : members) plane.push_back({total_seconds(report.runs[i], frames), *report.runs[i].metric(report.primary)});
      int order = 0;
      for (size_t f : pareto_front(plane, better_y)) {
        json row = run_row(report, members[f]);
        row["panel"] = panel;
        row["total_s"] = plane[f].time;
        row["y"] = plane[f].value;
        row["order"] = order++;
        row["series"] = report.variants[group.first].name + " " + group.second;
        lines.push_back(row);
      }
    }
    for (size_t i : runs) {
      json row = run_row(report, i);
      row["panel"] = panel;
      row["frames"] = frames;
      row["total_s"] = total_seconds(report.runs[i], frames);
      row["prepare_s"] = report.runs[i].quantity("prepare_seconds").value_or(0.0);
      row["y"] = *report.runs[i].metric(report.primary);
      ys.push_back(row["y"].get<double>());
      points.push_back(row);
    }
  }
  bool log_y = all_positive(ys);
  json x = axis("total_s", "total cost, s (log)", true);
  json y = axis("y", axis_title(report.primary, log_y), log_y);
  json tip = json::array({{{"field", "label"}, {"title", "run"}},
                          {{"field", "panel"}, {"title", "frames"}},
                          {{"field", "total_s"}, {"title", "total s"}, {"format", ".4g"}},
                          {{"field", "prepare_s"}, {"title", "prepare s"}, {"format", ".4g"}},
                          {{"field", "frame_ms"}, {"title", "frame ms"}, {"format", ".4g"}},
                          {{"field", "y"}, {"title", report.primary}, {"format", ".4g"}}});
  json point_encoding = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"tooltip", tip}};
  add_variant_shape(report, point_encoding);
  json line_encoding = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"order", {{"field", "order"}}},
                        {"detail", {{"field", "series"}}}};
  json panel_order = json::array();
  for (double frames : report.total_cost_frames) panel_order.push_back(fmt::format("N = {} frames", count_text(frames)));
  json spec = base_spec(fmt::format("Total cost over N frames: {} versus prepare + N \u00d7 frame time", report.primary),
                        "one panel per frame count; lines = each method's front in that panel");
  spec.erase("width");
  spec.erase("height");
  // Vega-Lite facets one data source: both layers' rows, told apart by "kind".
  json rows = json::array();
  for (json row : lines) {
    row["kind"] = "front";
    rows.push_back(row);
  }
  for (json row : points) {
    row["kind"] = "run";
    rows.push_back(row);
  }
  spec["data"] = {{"values", rows}};
  spec["facet"] = {{"column", {{"field", "panel"}, {"type", "nominal"}, {"title", nullptr}, {"sort", panel_order}}}};
  json line_layer = {{"transform", json::array({{{"filter", "datum.kind === 'front'"}}})},
                     {"mark", {{"type", "line"}, {"strokeWidth", 2}}},
                     {"encoding", line_encoding}};
  json point_layer = {{"transform", json::array({{{"filter", "datum.kind === 'run'"}}})},
                      {"mark", {{"type", "point"}, {"filled", true}, {"size", 50}}},
                      {"encoding", point_encoding}};
  spec["spec"] = {{"width", 190}, {"height", 220}, {"layer", json::array({line_layer, point_layer})}};
  // Each panel its own cost range: at N = 216000 every run costs hours, at N = 1 seconds.
  spec["resolve"] = {{"scale", {{"x", "independent"}}}};
  report.plots.push_back(
      {"plot-total-cost",
       fmt::format("Total cost of rendering N frames, prepare seconds + N \u00d7 median frame time, against {} ({}), "
                   "for N = {}. A method that precomputes starts to the right and moves left of the others as N grows; "
                   "the break-even table gives the frame count at which it overtakes each other method at equal or "
                   "better error.",
                   report.primary, direction_text(report.primary), frame_counts_text(report.total_cost_frames)),
       spec});
}

}  // namespace

void make_tradeoff_plots(Report& report) {
  for (size_t t = 0; t < report.tradeoffs.size(); ++t) make_tradeoff_plot(report, report.tradeoffs[t], t == 0);
  make_total_cost_plot(report);
}

}  // namespace causticbench::report_detail
