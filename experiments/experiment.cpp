#include "experiments/experiment.h"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/files.h"
#include "core/hash.h"
#include "core/scene_description.h"
#include "experiments/capability_matrix_settings.h"
#include "experiments/method_entries.h"
#include "store/result_paths.h"
#include "methods/lifecycle.h"
#include "methods/plugins.h"
#include "metrics/metrics.h"

namespace causticbench {

namespace fs = std::filesystem;

namespace {

// Experiment and variant names become folder and file names (with prefixes and suffixes such as
// "reference_<variant>_<n>.png" and "<name>.lock.partial"): checked against the file system's limit of 255
// bytes a name before any work (issue 30, defect 10), with room for those.
constexpr size_t kMaximumNameLength = 100;


nlohmann::json read_overrides(const ConfigNode& node, Scene& scene) {
  nlohmann::json applied = nlohmann::json::object();
  if (node.has("resolution")) {
    std::vector<double> resolution = node.numbers("resolution", 2, 1, 16384);
    set_resolution(scene, static_cast<int>(resolution[0]), static_cast<int>(resolution[1]));
    applied["resolution"] = {scene.camera.width, scene.camera.height};
  }
  if (std::optional<ConfigNode> camera = node.optional_child("camera")) {
    if (camera->has("position")) {
      glm::dvec3 p = camera->vec3("position");
      scene.camera.position = Vec3Track::constant(p);
      applied["camera"]["position"] = {p.x, p.y, p.z};
    }
    if (camera->has("look_at")) {
      glm::dvec3 p = camera->vec3("look_at");
      scene.camera.look_at = Vec3Track::constant(p);
      applied["camera"]["look_at"] = {p.x, p.y, p.z};
    }
    if (camera->has("fov_degrees")) {
      scene.camera.fov_degrees = camera->number("fov_degrees", 0.01, 179.0);
      applied["camera"]["fov_degrees"] = scene.camera.fov_degrees;
    }
    camera->finish();
    // The override may bring the camera onto its look_at, or its view onto `up`, at any frame.
    check_camera_at_every_frame(scene.camera, scene.frames, *camera);
  }
  if (std::optional<ConfigNode> light_node = node.optional_child("light")) {
    int index = light_node->integer_or("index", 0, 0, static_cast<int>(scene.lights.size()) - 1);
    Light& light = scene.lights[index];
    nlohmann::json& out = applied["light"];
    out["index"] = index;
    if (light_node->has("direction")) {
      glm::dvec3 d = light_node->vec3("direction");
      if (!light_direction_defect(d).empty()) {
        light_node->fail("direction", "a non-zero, finite direction of length in [1e-12, 1e12]",
                         fmt::format("[{}, {}, {}]", d.x, d.y, d.z));
      }
      light.direction = Vec3Track::constant(d);
      out["direction"] = {d.x, d.y, d.z};
    }
    if (light_node->has("position")) {
      glm::dvec3 p = light_node->vec3("position");
      light.position = Vec3Track::constant(p);
      out["position"] = {p.x, p.y, p.z};
    }
    if (light_node->has("irradiance")) {
      glm::dvec3 e = light_node->rgb("irradiance", 0.0, 1e9);
      light.irradiance = Color(e);
      out["irradiance"] = {e.x, e.y, e.z};
    }
    if (light_node->has("intensity")) {
      glm::dvec3 i = light_node->rgb("intensity", 0.0, 1e12);
      light.intensity = Color(i);
      out["intensity"] = {i.x, i.y, i.z};
    }
    if (light_node->has("solid_angle_sr")) {
      light.solid_angle = light_node->number("solid_angle_sr", 0.0, 2.0 * kPiDouble);
      out["solid_angle_sr"] = light.solid_angle;
    }
    light_node->finish();
  }
  node.finish();
  return applied;
}

// A scene file named by `key` of `node`, relative to the experiment file: its path, the hash of exactly
// the text that is parsed, and the scene.
SceneVariant read_scene_file(const ConfigNode& node, const std::string& key, const std::string& experiment_path) {
  std::string scene_name = node.string(key);
  fs::path scene_path = fs::path(experiment_path).parent_path() / scene_name;
  if (fs::path(scene_name).is_absolute()) scene_path = scene_name;
  if (!fs::is_regular_file(scene_path)) {
    throw_input_error(node.location_of(key), node.path().empty() ? key : node.path() + "." + key,
                      "a scene file (relative to the experiment file)",
                      "'" + scene_path.string() + "', which does not exist");
  }
  SceneVariant variant;
  variant.name = "default";
  variant.overrides = nlohmann::json::object();
  variant.scene_path = scene_path.lexically_normal().string();
  std::string scene_text = read_text(variant.scene_path);
  variant.scene_hash = hash_text(scene_text);
  variant.scene = load_scene_text(scene_text, variant.scene_path);
  return variant;
}

// `variants`: a list of override maps (the keys of `overrides`, plus an optional `name` and `scene`), each
// applied on top of the base overrides. A variant with its own `scene` starts from that file, with the
// base overrides applied to it. Without `variants`, the base is the one variant, named "default".
std::vector<SceneVariant> read_variants(const ConfigNode& root, const SceneVariant& base,
                                        const std::optional<ConfigNode>& base_overrides, const std::string& path) {
  std::optional<ConfigNode> list = root.optional_child("variants");
  if (!list) return {base};
  if (!list->is_sequence() || list->size() == 0) list->fail_here("a non-empty list of override maps", list->describe_value());
  std::vector<SceneVariant> variants;
  std::set<std::string> names;
  for (size_t i = 0; i < list->size(); ++i) {
    ConfigNode item = list->at(i);
    if (!item.is_map()) {
      item.fail_here("a map of overrides (resolution, camera, light), an optional name and an optional scene",
                     item.describe_value());
    }
    SceneVariant variant = base;
    if (item.has("scene")) {
      variant = read_scene_file(item, "scene", path);
      if (base_overrides) variant.overrides = read_overrides(*base_overrides, variant.scene);
    }
    variant.name = item.string_or("name", "");
    if (!variant.name.empty() && !std::regex_match(variant.name, std::regex("[A-Za-z0-9_.-]+"))) {
      item.fail("name", "a name of letters, digits, '_', '.' and '-'", "'" + variant.name + "'");
    }
    if (variant.name.size() > kMaximumNameLength) {
      item.fail("name", fmt::format("a name of at most {} characters (the report names files after it, and a file "
                                    "name holds at most 255 bytes)", kMaximumNameLength),
                fmt::format("{} characters", variant.name.size()));
    }
    nlohmann::json own = read_overrides(item, variant.scene);
    variant.overrides.merge_patch(own);
    if (variant.name.empty()) {
      if (item.has("scene") && own.empty()) {
        variant.name = fs::path(variant.scene_path).stem().string();
      } else if (own.size() == 1 && own.contains("resolution") && !item.has("scene")) {
        variant.name = fmt::format("{}x{}", variant.scene.camera.width, variant.scene.camera.height);
      } else {
        variant.name = fmt::format("variant{}", i);
      }
    }
    if (!names.insert(variant.name).second) {
      item.fail_here("variants with different names (set `name`)", "a second variant named '" + variant.name + "'");
    }
    for (const SceneVariant& earlier : variants) {
      if (earlier.overrides == variant.overrides && earlier.scene_hash == variant.scene_hash) {
        item.fail_here("variants that differ in their scene or overrides",
                       "the same overrides as variant '" + earlier.name + "', on the same scene");
      }
    }
    variants.push_back(std::move(variant));
  }
  return variants;
}

std::vector<int> read_frames(const ConfigNode& root, const Scene& scene) {
  std::vector<int> frames;
  if (!root.has("frames")) return {0};
  ConfigNode node = root.child("frames");
  if (node.is_scalar()) {
    if (node.as_string() != "all") node.fail_here("'all', a list of frame indices, or {first, count}", node.describe_value());
    for (int f = 0; f < scene.frames; ++f) frames.push_back(f);
  } else if (node.is_sequence()) {
    std::map<int, SourceLocation> first_seen;
    for (size_t i = 0; i < node.size(); ++i) {
      ConfigNode item = node.at(i);
      double value = item.as_number();
      if (value < 0 || value >= scene.frames || value != static_cast<int>(value)) {
        item.fail_here(fmt::format("a frame index in 0 .. {} (the scene has {} frames)", scene.frames - 1, scene.frames),
                       item.describe_value());
      }
      // A repeated frame would be played, timed and measured twice as if it were another frame.
      auto [earlier, inserted] = first_seen.insert({static_cast<int>(value), item.location()});
      if (!inserted) {
        item.fail_here("each frame index once", fmt::format("frame {} again (first at {})", earlier->first,
                                                            earlier->second.describe()));
      }
      frames.push_back(static_cast<int>(value));
    }
  } else {
    int first = node.integer("first", 0, scene.frames - 1);
    int count = node.integer("count", 1, scene.frames - first);
    node.finish();
    for (int f = first; f < first + count; ++f) frames.push_back(f);
  }
  if (frames.empty()) node.fail_here("at least one frame", "none");
  return frames;
}

// The folders the store keeps in the results root beside the experiments' (ResultPaths): the
// reference cache and the build cache.
std::vector<std::string> store_folder_names() {
  ResultPaths paths{""};
  return {fs::path(paths.reference("key")).parent_path().filename().string(),
          fs::path(paths.builds()).filename().string()};
}

// The name is a folder of the results root (RESULTS/<name>/): it must stay inside that root and keep
// out of the store's own folders, or its runs and report land beside the root or in a cache.
void check_experiment_name(const ConfigNode& root, const std::string& name) {
  std::string found = "'" + name + "'" + (root.has("name") ? "" : " (from the file name; set `name:`)");
  if (!std::regex_match(name, std::regex("[A-Za-z0-9_.-]+"))) {
    root.fail("name", "a name of letters, digits, '_', '.' and '-' (it names the results folder)", found);
  }
  if (name.size() > kMaximumNameLength) {
    root.fail("name", fmt::format("a name of at most {} characters (it names the results folder and the files in it, "
                                  "and a file name holds at most 255 bytes)", kMaximumNameLength),
              fmt::format("{} characters{}", name.size(), root.has("name") ? "" : " (from the file name; set `name:`)"));
  }
  if (name.front() == '.') {
    root.fail("name", "a name that does not start with '.' (it names a folder inside --results; '.' and '..' would "
                      "write into the results folder itself or its parent)", found);
  }
  std::vector<std::string> reserved = store_folder_names();
  if (std::find(reserved.begin(), reserved.end(), name) != reserved.end()) {
    root.fail("name", fmt::format("a name other than {} (the results store keeps its reference and build caches in "
                                  "those folders)", join(reserved, " and ")), found);
  }
}

// Metrics: named ones, or every per-frame metric (plus flicker for animations); the primary one among them.
void read_metrics(const ConfigNode& root, Experiment& experiment) {
  if (std::optional<ConfigNode> metrics = root.optional_child("metrics")) {
    // Blamed here, not on primary_metric: an empty list measures nothing.
    if (metrics->size() == 0) {
      metrics->fail_here("at least one metric name (or no `metrics` key: every metric)", "an empty list");
    }
    for (size_t i = 0; i < metrics->size(); ++i) {
      ConfigNode item = metrics->at(i);
      std::string name = item.as_string();
      try {
        find_metric(name);
      } catch (const InputError& error) {
        throw_input_error(item.location(), item.path(), "a metric name", std::string(error.what()));
      }
      if (std::find(experiment.metrics.begin(), experiment.metrics.end(), name) != experiment.metrics.end()) {
        item.fail_here("each metric once", "'" + name + "' again");
      }
      experiment.metrics.push_back(name);
    }
  } else {
    for (const MetricInfo& metric : metric_registry()) {
      if (metric.per_frame || experiment.frames.size() > 1) experiment.metrics.push_back(metric.name);
    }
  }
  experiment.primary_metric = root.string_or("primary_metric", "relmse");
  if (std::find(experiment.metrics.begin(), experiment.metrics.end(), experiment.primary_metric) == experiment.metrics.end()) {
    // Without the key the default is what is missing from `metrics`: point there, not at line 1.
    if (!root.has("primary_metric")) {
      root.fail("metrics", "a list that holds relmse (the default primary_metric), or a primary_metric naming one of " +
                               join(experiment.metrics, ", "), "no relmse");
    }
    root.fail("primary_metric", "one of the experiment's metrics: " + join(experiment.metrics, ", "),
              "'" + experiment.primary_metric + "'");
  }
}

// The reference's knobs, and each variant's reference key and content hash from them.
void read_reference(const ConfigNode& root, Experiment& experiment) {
  ParamDict reference_dict;
  if (std::optional<ConfigNode> reference = root.optional_child("reference")) reference_dict.set_from_config(*reference);
  experiment.reference_params = reference_dict.resolve(find_method("reference").info().params, "reference");
  for (SceneVariant& variant : experiment.variants) {
    variant.content_hash = hash_json(scene_content_json(variant.scene));
    variant.reference_key = hash_json({{"scene_hash", variant.scene_hash},
                                       {"overrides", variant.overrides},
                                       {"reference", experiment.reference_params.to_json()}});
  }
}

}  // namespace

std::vector<std::string> Experiment::variant_names() const {
  std::vector<std::string> names;
  for (const SceneVariant& variant : variants) names.push_back(variant.name);
  return names;
}

nlohmann::json Experiment::to_json() const {
  nlohmann::json runs_json = nlohmann::json::array();
  for (const RunSpec& run : runs) runs_json.push_back(run.key);
  nlohmann::json variants_json = nlohmann::json::array();
  for (const SceneVariant& variant : variants) {
    variants_json.push_back({{"name", variant.name},
                             {"scene", variant.scene_path},
                             {"overrides", variant.overrides},
                             {"resolution", {variant.scene.camera.width, variant.scene.camera.height}},
                             {"reference_key", variant.reference_key}});
  }
  nlohmann::json out = {{"name", name},
          {"source", source},
          {"description", description},
          {"scene", scene_path},
          {"scene_hash", scene_hash},
          {"overrides", variants.front().overrides},
          {"resolution", {variants.front().scene.camera.width, variants.front().scene.camera.height}},
          {"variants", variants_json},
          {"frames", frames},
          {"repetitions", repetitions},
          {"seeds", seeds},
          {"pixel_samples", pixel_samples},
          {"metrics", metrics},
          {"primary_metric", primary_metric},
          {"reference", reference_params.to_json()},
          {"reference_key", variants.front().reference_key},
          {"runs", runs_json},
          {"paper", report.paper},
          {"claims", report.claims},
          {"tradeoffs", report.tradeoffs_json()},
          {"budgets_ms", report.budgets_ms},
          {"error_targets", report.error_targets},
          {"total_cost_frames", report.total_cost_frames},
          {"case_table", report.case_table},
          {"empty_reference_expected", empty_reference_expected}};
  // Only where declared, so that every other experiment.json stays as it was.
  if (!report.capability_matrix.is_null()) out["capability_matrix"] = report.capability_matrix;
  if (!plugins.empty()) out["plugins"] = plugins;
  return out;
}

namespace {

// `plugins:`: shared libraries whose methods the entries may name, each path relative to the file.
void read_plugins(const ConfigNode& root, Experiment& experiment) {
  std::optional<ConfigNode> list = root.optional_child("plugins");
  if (!list) return;
  if (!list->is_sequence()) list->fail_here("a list of plugin paths (shared libraries, relative to this file)", list->describe_value());
  for (size_t i = 0; i < list->size(); ++i) {
    const ConfigNode entry = list->at(i);
    if (!entry.is_scalar()) entry.fail_here("a plugin path", entry.describe_value());
    fs::path path = entry.as_string();
    if (path.is_relative()) path = fs::path(experiment.source).parent_path() / path;
    try {
      experiment.plugins.push_back(load_plugin(path.string()).to_json());
    } catch (const InputError& failure) {
      throw InputError(fmt::format("{}: key '{}': {}", entry.location().describe(), entry.path(), failure.what()));
    }
  }
}

}  // namespace

Experiment load_experiment(const std::string& path) {
  ConfigNode root = ConfigNode::load_file(path);
  if (!root.is_map()) root.fail_here("an experiment map with scene and methods", root.describe_value());
  Experiment experiment;
  experiment.source = path;
  experiment.name = root.string_or("name", fs::path(path).stem().string());
  check_experiment_name(root, experiment.name);
  experiment.description = root.string_or("description", "");
  SceneVariant base = read_scene_file(root, "scene", path);
  experiment.scene_path = base.scene_path;
  experiment.scene_hash = base.scene_hash;
  std::optional<ConfigNode> base_overrides = root.optional_child("overrides");
  if (base_overrides) base.overrides = read_overrides(*base_overrides, base.scene);
  experiment.variants = read_variants(root, base, base_overrides, path);
  experiment.frames = read_frames(root, experiment.variants.front().scene);
  // A variant with its own scene may have fewer frames than the first variant that `frames` was read
  // against.
  for (const SceneVariant& variant : experiment.variants) {
    for (int frame : experiment.frames) {
      if (frame >= variant.scene.frames) {
        root.fail("frames", fmt::format("frames that every variant's scene has (variant '{}', {}, has {})", variant.name,
                                        variant.scene_path, variant.scene.frames),
                  fmt::format("frame {}", frame));
      }
    }
  }
  experiment.repetitions = root.integer_or("repetitions", 3, 1, 1000);
  experiment.seeds = static_cast<int>(root.integer_or("seeds", 1, 1, 1000));
  experiment.pixel_samples = static_cast<int>(root.integer_or("pixel_samples", 1, 1, 256));
  if (!valid_pixel_samples(experiment.pixel_samples)) {
    root.fail("pixel_samples", "a square number of points per pixel (1, 4, 9, 16, ..., 256)",
              std::to_string(experiment.pixel_samples));
  }
  experiment.empty_reference_expected = root.boolean_or("empty_reference_expected", false);

  read_metrics(root, experiment);
  read_reference(root, experiment);
  read_plugins(root, experiment);

  // Counted before anything is expanded: a run costs a few kilobytes to resolve and hash, so a
  // mistaken sweep product (10^6, 10^9 runs) must be refused with its count, not exhaust memory.
  RunCount count{root.integer_or("max_runs", kDefaultMaximumRuns, 1, kLargestMaximumRuns)};
  ConfigNode methods = root.child("methods");
  if (methods.size() == 0) methods.fail_here("at least one method entry", "an empty list");
  for (size_t m = 0; m < methods.size(); ++m) add_method_entry(methods.at(m), experiment, count);
  experiment.report = read_report_settings(root, experiment.metrics, experiment.primary_metric, experiment.variant_names());
  if (std::optional<ConfigNode> matrix = root.optional_child("capability_matrix"))
    experiment.report.capability_matrix = read_capability_matrix(*matrix, experiment);
  root.finish();
  return experiment;
}

std::vector<std::pair<std::string, std::string>> experiment_file_runs(const std::string& path) {
  std::vector<std::pair<std::string, std::string>> runs;
  try {
    for (const RunSpec& run : load_experiment(path).runs) runs.push_back({run.key, run.method});
  } catch (const std::exception&) {
    runs.clear();  // moved or changed beyond reading: the caller falls back on what it has
  }
  return runs;
}

}  // namespace causticbench
