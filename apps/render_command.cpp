#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/direct_lighting.h"
#include "core/files.h"
#include "core/image_statistics.h"
#include "core/parallel.h"
#include "methods/lifecycle.h"
#include "methods/method_runner.h"
#include "metrics/caustic_presence.h"
#include "store/build_cache.h"
#include "store/result_paths.h"

namespace causticbench {

void parse_resolution(const std::string& text, int& width, int& height) {
  size_t x = text.find('x');
  try {
    size_t used_w = 0, used_h = 0;
    if (x == std::string::npos) throw std::invalid_argument("no x");
    width = std::stoi(text.substr(0, x), &used_w);
    height = std::stoi(text.substr(x + 1), &used_h);
    if (used_w != x || used_h != text.size() - x - 1 || width < 1 || height < 1 || width > 16384 || height > 16384) {
      throw std::invalid_argument("range");
    }
  } catch (const std::exception&) {
    throw InputError(fmt::format("--resolution: expected WIDTHxHEIGHT with each in [1, 16384], found '{}'", text));
  }
}

Scene load_scene_at_resolution(const std::string& path, const std::string& resolution) {
  Scene scene = load_scene(path);
  if (!resolution.empty()) {
    int width, height;
    parse_resolution(resolution, width, height);
    set_resolution(scene, width, height);
  }
  return scene;
}

// A reference with no caustic in view is what stops an experiment (exit code 2): say so here already, by
// the same rule (metrics/caustic_presence.h).
void warn_if_reference_is_empty(const RenderOptions& options, const FrameResult& result, const Image& direct) {
  if (options.method != "reference") return;
  CausticPresence presence = measure_caustic_presence(result.caustic, direct, result.gbuffer.receiver);
  if (!presence.empty()) return;
  fmt::print(stderr,
             "warning: the reference of scene {} has no caustic in view on frame {}: {}; {}. An experiment on this "
             "scene and view stops before any method runs (exit code 2) unless it sets "
             "`empty_reference_expected: true`.\n",
             options.scene, options.frame, presence.describe(), kEmptyCausticHint);
}

// The render and its files, into folders that exist.
static void render_and_write(const RenderOptions& options, const Scene& scene, const RenderRequest& request,
                             const CheckedRequest& checked);

int run_render(const RenderOptions& options) {
  // Everything is checked before any work starts.
  Scene scene = load_scene_at_resolution(options.scene, options.resolution);
  RenderRequest request;
  request.scene = &scene;
  request.method = options.method;
  request.frame = options.frame;
  request.dump_folder = options.dump_frame;
  if (!valid_pixel_samples(options.pixel_samples)) {
    throw InputError(fmt::format("--pixel-samples: expected a square number of points per pixel (1, 4, 9, ..., 256), found {}",
                                 options.pixel_samples));
  }
  request.pixel_samples = options.pixel_samples;
  // Checked like --results before any work: a file there, or a folder that cannot be written, would
  // otherwise fail only after the build was computed.
  if (!options.build_cache.empty()) check_writable_folder("--build-cache", "stored builds", options.build_cache);
  std::optional<BuildCacheFolder> builds;
  if (!options.build_cache.empty()) request.builds = &builds.emplace(options.build_cache);
  std::map<std::string, std::string> given;  // knob -> its --set, so that a repeated one is refused
  for (const std::string& assignment : options.assignments) {
    // The last of two would win silently: a slip in a long command line must not pass unnoticed.
    const std::string knob = assignment.substr(0, assignment.find('='));
    if (auto [previous, added] = given.emplace(knob, assignment); !added) {
      throw InputError(fmt::format("--set: expected each knob once, found '{}' twice ('{}' and '{}')", knob,
                                   previous->second, assignment));
    }
    request.params.set_assignment(assignment, "--set");
  }
  CheckedRequest checked = check_request(request);
  namespace fs = std::filesystem;
  // Made now so that an unwritable --out stops before the render; removed again if the render fails
  // before anything is written into it, so that a failure leaves no empty folder behind.
  std::vector<std::string> created;
  for (const std::string& folder : {options.out, options.dump_frame}) {
    if (folder.empty()) continue;
    bool existed = fs::exists(folder);
    ensure_folder(folder);  // also refuses a file of that name
    if (!existed) created.push_back(folder);
  }
  try {
    render_and_write(options, scene, request, checked);
  } catch (...) {
    std::error_code ignored;
    for (const std::string& folder : created) {
      if (fs::is_empty(folder, ignored)) fs::remove(folder, ignored);
    }
    throw;
  }
  return 0;
}

static void render_and_write(const RenderOptions& options, const Scene& scene, const RenderRequest& request,
                             const CheckedRequest& checked) {
  ThreadLimit limit(options.threads);
  fmt::print(stderr, "rendering {} with {} at {}x{}, frame {}\n", options.scene, options.method, scene.camera.width,
             scene.camera.height, options.frame);
  Image direct;
  FrameResult result = run_frame(request, checked, &direct, options.direct_samples);

  namespace fs = std::filesystem;
  std::string out = options.out;
  write_exr(result.caustic, (fs::path(out) / "caustic.exr").string());
  write_exr(direct, (fs::path(out) / "direct.exr").string());
  write_exr(result.gbuffer.to_image(), (fs::path(out) / "gbuffer.exr").string(), GBuffer::channel_names());
  Image composite = composite_radiance(result.gbuffer, direct, result.caustic);
  // Expose so that the mean radiance of the receivers maps to a mid grey.
  double mean = masked_mean(composite, result.gbuffer.receiver);
  float exposure = mean > 0.0 ? static_cast<float>(0.18 / mean) : 1.0f;
  write_png(composite, (fs::path(out) / "composite.png").string(), exposure);
  double caustic_mean = masked_mean(result.caustic, result.gbuffer.receiver);
  write_png(result.caustic, (fs::path(out) / "caustic.png").string(),
            caustic_mean > 0.0 ? static_cast<float>(0.18 / caustic_mean) : 1.0f);

  nlohmann::json counters = nlohmann::json::object();
  nlohmann::json gpu_time = result.timings.gpu_render_milliseconds ? nlohmann::json(*result.timings.gpu_render_milliseconds)
                                                                   : nlohmann::json(nullptr);
  for (const auto& [name, value] : result.counters) counters[name] = value;
  nlohmann::json record = {
      {"scene", options.scene},
      {"scene_name", scene.name},
      {"method", options.method},
      {"params", checked.params.to_json()},
      {"frame", options.frame},
      {"pixel_samples", options.pixel_samples},
      {"resolution", {scene.camera.width, scene.camera.height}},
      {"receiver_pixels", result.gbuffer.receiver_count()},
      {"timings", {{"prepare_seconds", result.timings.prepare_seconds},
                   {"update_milliseconds", result.timings.update_milliseconds},
                   {"render_milliseconds", result.timings.render_milliseconds}}},
      {"prepare", {{"source", result.prepare.source},
                   {"build_key", result.prepare.build_key},
                   {"load_seconds", result.prepare.load_seconds},
                   {"save_seconds", result.prepare.save_seconds}}},
      {"gpu_render_milliseconds", gpu_time},
      {"memory_bytes", result.memory_bytes},
      {"counters", counters},
      {"method_record", result.method_record},
      {"lost_flux", result.lost_flux ? lost_flux_json(*result.lost_flux) : nlohmann::json(nullptr)},
      {"caustic_flux_on_receivers", masked_sum(result.caustic, result.gbuffer.receiver)},
      {"environment", environment_json(options.threads)},
      {"files", {"caustic.exr", "direct.exr", "gbuffer.exr", "composite.png", "caustic.png"}}};
  write_text_atomically((fs::path(out) / "record.json").string(), record.dump(2) + "\n");
  warn_if_reference_is_empty(options, result, direct);
  if (result.lost_flux && result.lost_flux->fraction > kLostFluxWarning)
    fmt::print(stderr, "warning: {} {}\n", options.method, describe_lost_flux(*result.lost_flux));
  fmt::print("wrote {}/caustic.exr, direct.exr, gbuffer.exr, composite.png, caustic.png, record.json\n", out);
}

}  // namespace causticbench
