// Helpers shared by the tests: scenes from strings, running a method on a frame, image regions.
#pragma once

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/sampling.h"
#include "methods/lifecycle.h"
#include "methods/method_runner.h"

namespace causticbench::testing {

// A glass sphere (radius 0.4) above a diffuse floor under a tilted directional light, 40 x 40 pixels.
// configs/scenes of the tree this build came from, or the installed copy beside the executable
// (share/causticbench/configs/scenes) once the tree is gone: what causticbench-conformance reads.
std::string shipped_scenes();

extern const char* const kSmallGlassSphere;
// The flat mirror of the caustic methods' tests, whose caustic is known in closed form: a 0.6 x 0.6
// mirror (reflectance 0.9) 1.5 above the floor, under a sun of irradiance 2 travelling at 45 degrees down
// towards +x, turned (112.5 degrees about z) so that it reflects the light straight down: the
// beam keeps its cross-section, the mirror's area times the cosine to the light (0.383), and lights a
// 0.6 x 0.230 rectangle of the floor with E = 2 x 0.9 = 1.8 exactly. (Under a horizontal sun the light
// would see the floor edge-on, and caustics mapping, which finds receivers in the light's view, none.)
// An orthographic camera under the mirror looks straight down, so that a pixel's area on the floor is
// exactly (1.2 / 96)^2 and the pixels' sum is the flux.
extern const char* const kFlatMirror;
inline constexpr double kBeamIrradiance = 1.8;
// A mirror sphere (radius 0.4, reflectance 0.9) under a point light close above it, seen in perspective,
// 48 x 48 pixels: a perspective light view and a fan of grazing rays (the GPU backends' agreement cases).
extern const char* const kMirrorSpherePointLight;
inline constexpr double kBeamHalfX = 0.3 * 0.38268343, kBeamHalfZ = 0.3;

// Reference knobs for the small scenes' method-against-reference tests: 6 x 200,000 photons, seed 7
// (not the methods' default seed).
extern const std::vector<std::string> kSmallSceneReferenceKnobs;

Scene scene_from_yaml(const std::string& yaml, const std::string& name = "test.yaml");

// A direction uniform over the unit sphere (z uniform in [-1, 1], azimuth uniform), in double.
glm::dvec3 random_direction(Random& random);

// The value of a run's counter `name`, or -1 where the method has none.
double counter_value(const FrameResult& result, const std::string& name);

// Runs `method` with the given "key=value" knobs on one frame.
FrameResult render(const Scene& scene, const std::string& method, const std::vector<std::string>& knobs, int frame = 0);

// Runs `method` on `frames` as an animation through the lifecycle (prepare() sees all of them, then
// update() and render() per frame, in order) and returns the result of frame `judged`, one of them.
FrameResult render_sequence(const Scene& scene, const std::string& method, const std::vector<std::string>& knobs,
                            const std::vector<int>& frames, int judged);

// `text` with the first occurrence of `from` replaced (a test failure when there is none).
std::string replace_once(std::string text, const std::string& from, const std::string& to);

// Empty when a Vulkan device answers (a GPU, or lavapipe), otherwise why not: the GPU backends' tests
// skip with it (CAUSTICBENCH_SKIP_WITHOUT_VULKAN).
std::string no_vulkan_device();
#define CAUSTICBENCH_SKIP_WITHOUT_VULKAN(what)                                                    \
  if (const std::string why = causticbench::testing::no_vulkan_device(); !why.empty()) {          \
    GTEST_SKIP() << "no Vulkan device for " << (what) << ": " << why;                             \
  }

// The message of the InputError that `action` throws, or "no error".
std::string input_error_message(const std::function<void()>& action);

// `text` with each line matching a pattern (a regular expression over one line, starting at its "\n")
// replaced; a test failure when a pattern matches nothing. How the study tests make tiny copies.
std::string replace_lines(std::string text, const std::vector<std::pair<std::string, std::string>>& lines);

// An experiment's text at `resolution` squared, with a two-pass reference of 100,000 photons and one
// repetition (its `overrides`, `reference` and `repetitions`, each a one-line value or a block of
// indented lines, replaced): what every tiny copy of a shipped experiment starts from.
std::string tiny_experiment(const std::string& text, int resolution);

// `scene` (a variant of kSmallGlassSphere's text) over two frames, its sun turning from (0.3, -1, 0.2) at
// frame 0 to (-0.1, -1, 0.1) at frame 1, a direction on no precomputed one: the dynamic-light scene of the
// csl tests.
std::string small_glass_sphere_turning(const std::string& scene = kSmallGlassSphere);

// `method`'s knobs from "name=value" assignments, resolved against its specs and split by phase.
PhaseKnobs method_knobs(const std::string& method, const std::vector<std::string>& knobs);

// The shipped experiment files (configs/experiments/*.yaml) whose names start with `prefix`, sorted.
std::vector<std::filesystem::path> shipped_experiments(const std::string& prefix);

// The whole text of a file ("" when it cannot be read).
std::string read_whole_file(const std::filesystem::path& path);

// Runs a shell command, returns its exit code and fills `output` with stdout+stderr.
int run_command(const std::string& command, std::string& output);

// The second half of a Vulkan backend's dump round trip, on a `dump` folder its method wrote: `gpubench`
// (causticbench-gpubench's path) replays it, and gpu_timings.json names `method` and holds `fact`; `binary`
// (causticbench's) gpu-compare finds the replay agreeing; the replay's output scaled by 0.99 disagrees
// (exit 1); `damaged_file` cut short by `cut` floats is refused (exit 2) with `damage_message`. Each
// check is a gtest expectation.
void expect_replay_round_trip(const std::string& gpubench, const std::string& binary, const std::string& dump,
                              const std::string& method, const std::string& fact, const std::string& damaged_file,
                              size_t cut, const std::string& damage_message);

// A Vulkan backend against its CPU backend: `method` rendered on `scene` with `knobs`, then with
// backend=vulkan added. The relMSE over the CPU run's receivers and the flux ratio minus 1 are printed
// after `what` and the knobs, and expected below `relmse_bound` and `flux_bound`; the CPU image must hold
// light. Both runs come back (`label`: what and the knobs) for the method's own checks of its counters.
struct BackendRuns {
  FrameResult cpu, vulkan;
  std::string label;
};
BackendRuns expect_backends_agree(const Scene& scene, const std::string& method, const std::vector<std::string>& knobs,
                                  const std::string& what, double relmse_bound, double flux_bound);

// A folder under the system's temporary folder, emptied when made and removed when destroyed.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& name);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  // Writes `text` to the file `name` in the folder; returns its path.
  std::string write(const std::string& name, const std::string& text) const;
  std::string path(const std::string& name = "") const;

 private:
  std::filesystem::path path_;
};

// Mean of channel 0 over receiver pixels whose position satisfies `inside`.
template <typename Predicate>
double region_mean(const FrameResult& result, Predicate inside, size_t* count = nullptr) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t pixel = 0; pixel < result.gbuffer.pixel_count(); ++pixel) {
    if (!result.gbuffer.receiver[pixel] || !inside(result.gbuffer.position[pixel])) continue;
    sum += result.caustic.at(pixel, 0);
    ++n;
  }
  if (count) *count = n;
  return n ? sum / static_cast<double>(n) : 0.0;
}

// The integral over solid angle of f(direction) across the square [-half_width, half_width]^2 of the
// plane tangent to the unit sphere at `axis` (gnomonic: dω = dA / (1 + x² + y²)^{3/2}), by the
// midpoint rule on steps x steps cells: what a light map's lookups around a compact light add up to.
template <class Function>
double integrate_around(const Vec3& axis, double half_width, int steps, Function f) {
  Vec3 tangent, bitangent;
  orthonormal_basis(axis, tangent, bitangent);
  const double step = 2.0 * half_width / steps;
  double integral = 0.0;
  for (int i = 0; i < steps; ++i) {
    for (int j = 0; j < steps; ++j) {
      const double x = -half_width + (i + 0.5) * step, y = -half_width + (j + 0.5) * step;
      const Vec3 direction = glm::normalize(axis + static_cast<float>(x) * tangent + static_cast<float>(y) * bitangent);
      integral += f(direction) * step * step * std::pow(1.0 + x * x + y * y, -1.5);
    }
  }
  return integral;
}

}  // namespace causticbench::testing
