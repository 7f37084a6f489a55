// lpi's declarations: its knobs with their phases, ranges and cross-knob rules, its capabilities and
// counters (methods/lpi/README.md's table is generated from them), and the volume settings the knobs give.
#include "methods/lpi/lpi.h"

#include <chrono>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "methods/common/gpu_arrays.h"
#include "methods/lpi/environment.h"
#include "methods/lpi/gpu_frame.h"
#include "methods/lpi/lookup.h"
#include "methods/lpi/multires_layout.h"
#include "methods/lpi/orientation_choice.h"
#include "methods/lpi/vulkan_lpi.h"
#include "methods/common/spherical_harmonics.h"

namespace causticbench {

using namespace lpi;

namespace {

// The paper's orientation stores irradiance across the direction from the object's centre to each
// sample point. A volume of one cell has its only sample at the centre, where that direction does not
// exist: every value would be 0 and the image black, silently (found by study_extremes_knobs.yaml).
std::string one_cell_paper_problem(bool one_cell, const std::string& cells, const std::string& more, const ParamSet& knobs) {
  if (!one_cell || knobs.text("orientation") != "paper") return "";
  return fmt::format("{} gives one cell, centred on the object, and orientation 'paper' needs the direction from the "
                     "object's centre to each sample point, which that cell lacks (its value would be 0): use {} or "
                     "orientation: vector",
                     cells, more);
}

std::string grid_one_cell_problem(const ParamSet& knobs) {
  return one_cell_paper_problem(knobs.integer("grid_resolution") == 1, "grid_resolution 1", "grid_resolution 2 or more", knobs);
}

std::string multires_one_cell_problem(const ParamSet& knobs) {
  return one_cell_paper_problem(knobs.integer("multires_depth") == 0, "multires_depth 0", "multires_depth 1 or more", knobs);
}

// Spherical harmonics over the light directions are fitted to the geodesic set's samples: (order + 1)^2
// coefficients need at least as many samples.
std::string sh_samples_problem(const ParamSet& knobs) {
  const int64_t order = knobs.integer("sh_order"), subdivision = knobs.integer("light_subdivision");
  const int64_t power = int64_t{1} << (2 * subdivision);
  const int64_t samples = knobs.text("light_sample_at") == "faces" ? 20 * power : 10 * power + 2;
  const int64_t coefficients = (order + 1) * (order + 1);
  if (coefficients <= samples) return "";
  return fmt::format("sh_order {} has {} coefficients a cell, more than the {} light samples of light_subdivision {} "
                     "can determine; raise light_subdivision or lower sh_order",
                     order, coefficients, samples, subdivision);
}

}  // namespace

const MethodInfo& LpiMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "lpi";
    m.paper = "C. Wyman, C. Hansen, P. Shirley, \"Interactive Raytraced Caustics\", Univ. of Utah UUCS-03-009, 2003 "
              "(local precomputed irradiance)";
    m.summary = "Precomputes each specular object's caustic irradiance in a volume around it (a grid, concentric "
                "geodesic shells or an adaptive octree; or per cell spherical harmonics over light directions) for a "
                "set of light directions, by photon tracks through the object alone; per frame "
                "it turns the light into the object's frame and looks the caustic up, blending neighbouring light samples "
                "(an environment map: every light sample, weighted by the map's light around it).";
    const std::vector<std::string> grid_or_sh = {"grid", "sh"}, shells = {"shells"}, multires = {"multires"}, sh = {"sh"};
    // sh fits over the whole sphere of light directions and reads no light sample by itself.
    const std::vector<std::string> sampled = {"grid", "shells", "multires"};
    m.params = {
        ParamSpec::choice("storage", "grid", {"grid", "shells", "multires", "sh"},
                          "how the volume is sampled: a uniform grid of cells, concentric shells sampled at geodesic "
                          "vertices (Section 4.2), an octree refined where the caustic varies, or per grid cell "
                          "spherical harmonics over light directions (Section 4.3)",
                          ParamPhase::build),
        ParamSpec::integer("grid_resolution", 64, 1, 512,
                           "cells along each axis of the grid over the sampled ball (sh: each holds its coefficients)",
                           ParamPhase::build)
            .only_when("storage", grid_or_sh),
        ParamSpec::integer("shell_count", 12, 1, 256, "concentric shells from the centre to volume_radius", ParamPhase::build)
            .only_when("storage", shells),
        ParamSpec::integer("shell_subdivision", 4, 0, 7,
                           "subdivisions of the icosahedron whose 10 4^s + 2 vertices sample each shell", ParamPhase::build)
            .only_when("storage", shells),
        ParamSpec::choice("shell_spacing", "uniform", {"uniform", "quadratic"},
                          "radii of the shells: uniform, or quadratic (r_k = R ((k + 1) / K)^2, denser near the object)",
                          ParamPhase::build)
            .only_when("storage", shells),
        ParamSpec::integer("multires_depth", 6, 0, 9,
                           "levels of the multires octree below its root: the finest cells are those of a 2^depth grid",
                           ParamPhase::build)
            .only_when("storage", multires),
        ParamSpec::real("error_threshold", 0.01, 0.0, 1.0,
                        "a multires subtree becomes one leaf, its mean, when every finest cell in it lies within "
                        "error_threshold x the light sample's largest value of that mean (every channel, and every light "
                        "sample the tree serves)",
                        ParamPhase::build)
            .only_when("storage", multires),
        // Added after experiments shipped: at shared it stays out of their run keys and build-cache keys,
        // so stored shared trees keep theirs; per_sample names builds of its own.
        ParamSpec::choice("multires_tree", "shared", {"shared", "per_sample"},
                          "shared: one octree for all light samples, refined where any sample's caustic varies (one "
                          "descent a receiver point); per_sample: an octree per light sample, refined only where its "
                          "own caustic varies (fewer values, its own tree words, a descent per read)",
                          ParamPhase::build)
            .only_when("storage", multires)
            .unkeyed_at_default(),
        ParamSpec::integer("sh_order", 4, 0, 9,
                           "highest degree of the spherical harmonics over light directions, (order + 1)^2 coefficients "
                           "a cell and channel (4: the paper's 5th order read as 5 bands, Fig. 9)",
                           ParamPhase::build)
            .only_when("storage", sh),
        ParamSpec::choice("precision", "float32", {"uint8", "float16", "float32"},
                          "stored value type; uint8 scales each light sample's values to 0..255 (the paper stored 3 bytes a colour)",
                          ParamPhase::build),
        ParamSpec::choice("orientation", "auto", {"auto", "paper", "vector"},
                          fmt::format("auto: paper where probe photons show its cosine renders the light landing on "
                                      "the scene's receivers within {:.0f} %, else vector; paper: irradiance on the "
                                      "surface facing the object's centre, corrected by the cosine to the receiver's "
                                      "normal (Section 3.2); vector: the vector irradiance, shaded max(0, n . E)",
                                      100.0 * kPaperOrientationTolerance),
                          ParamPhase::build),
        ParamSpec::real("volume_radius", 3.0, 0.01, 1000.0,
                        "radius of the sampled ball, in bounding radii of the object; auto: the smallest ball holding "
                        "98 % of where the object's light first meets a receiver in the rendered frames (probe "
                        "photons at prepare), times 1.1, capped where the storage stops resolving the object",
                        ParamPhase::build)
            .auto_by_default(),
        ParamSpec::integer("photons_per_sample", 1000000, 1, 4e9, "photons shot at the object per light sample",
                           ParamPhase::build),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the photon paths", ParamPhase::build),
        ParamSpec::choice("light_samples", "auto", {"auto", "all"},
                          "auto: when no light's direction in an object's frame changes over the rendered frames, just "
                          "those directions; with an environment light, the geodesic samples its map lights; otherwise "
                          "(and with all) the geodesic set",
                          ParamPhase::build)
            .only_when("storage", sampled),
        ParamSpec::integer("light_subdivision", 2, 0, 6,
                           "subdivisions of the icosahedron of light directions (2: 162 vertices, as for the bunny)",
                           ParamPhase::build),
        ParamSpec::choice("light_sample_at", "vertices", {"vertices", "faces"},
                          "light samples at the geodesic's vertices (10 4^s + 2) or face centres (20 4^s)", ParamPhase::build),
        ParamSpec::choice("symmetry", "none", {"none", "axial", "spherical"},
                          "axial: samples on one meridian of the object's local y axis, the lookup turns the light about "
                          "it; spherical: one sample, every direction turned onto it",
                          ParamPhase::build)
            .only_when("storage", sampled),
        ParamSpec::choice("blend", "barycentric", {"nearest", "barycentric", "aligned"},
                          "nearest light sample (pops), barycentric blend of three (ghosts), or aligned: each of the "
                          "three read at the point turned by the angle between it and the light (Section 5.2)",
                          ParamPhase::frame)
            .only_when("storage", sampled),
        // Added after experiments shipped: at combined it stays out of their run keys.
        ParamSpec::choice("environment_clamp", "combined", {"combined", "per_sample"},
                          "environment lights, orientation vector: combined: the light samples' volumes summed into one "
                          "and shaded max(0, n . E) once; per_sample: each sample shaded max(0, n . E_s), then weighted "
                          "and summed (every sample read a pixel)",
                          ParamPhase::frame)
            .only_when("storage", sampled)
            .unkeyed_at_default(),
        ParamSpec::choice("outside", "clamp", {"clamp", "fade", "zero"},
                          "beyond the sampled ball: the value on its surface (clamp), that times (R / d)^2 (fade), or none",
                          ParamPhase::render),
        // Added after experiments shipped: at cpu it stays out of their run keys.
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "cpu (multithreaded) or vulkan (compute shader, storage grid and shells; lavapipe without a GPU)",
                          ParamPhase::build)
            .unkeyed_at_default(),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = true;
    c.directional_light = c.environment_light = true;
    c.moving_light = c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {
        {"multiple_bounces", "any number within one object (glass in and out, a ring's self-reflections); none between "
                             "objects: each object's caustic is precomputed alone"},
        {"point_light", "taken as a directional light from the object's centre, with the irradiance there"},
        {"environment_light", "beyond the paper: the light samples' volumes weighted by the map's light over each "
                              "sample's barycentric hat function (storage: sh: a dot product with the map's projection, "
                              "as precomputed radiance transfer); not with symmetry axial or spherical"},
        {"moving_light", "light samples over the directions the light takes in the object's frame, blended per frame"},
        {"moving_objects", "the caustic moves and turns with its object; a changing scale is not followed"},
        {"occlusion", "the caustic reaches receivers behind other objects"},
        {"non_lambertian_receivers", "E_c is irradiance, whatever the receiver's BRDF"},
    };
    m.knob_rules = {{{"grid_resolution", "orientation"}, grid_one_cell_problem},
                    {{"multires_depth", "orientation"}, multires_one_cell_problem},
                    {{"sh_order", "light_subdivision", "light_sample_at"}, sh_samples_problem}};
    m.quick_knobs = {"photons_per_sample=20000", "light_subdivision=0"};
    m.counters = {counter_quantity("light_samples", "samples", "light directions precomputed (over all objects)"),
                  counter_quantity("photons_emitted", "photons", "photons shot over all light samples and objects"),
                  counter_quantity("shoot_seconds_per_light_sample", "s", "precomputation time per light sample",
                                   QuantityKind::timing),
                  counter_quantity("bytes_per_light_sample", "bytes", "stored irradiance per light sample",
                                   QuantityKind::size),
                  counter_quantity("volume_reads_per_frame", "reads",
                                   "interpolated volume reads of the last frame rendered: receiver points x light "
                                   "samples read, over objects and lights (divided by render_ms: the lookup rate)")};
    return m;
  }();
  return info;
}

VolumeSettings lpi::volume_settings(const ParamSet& build) {
  VolumeSettings settings;
  const std::string storage = build.text("storage");
  settings.storage = storage == "grid"       ? StorageKind::grid
                     : storage == "shells"   ? StorageKind::shells
                     : storage == "multires" ? StorageKind::multires
                                             : StorageKind::sh;
  if (settings.storage == StorageKind::grid || settings.storage == StorageKind::sh) {
    settings.grid_resolution = static_cast<int>(build.integer("grid_resolution"));
  }
  if (settings.storage == StorageKind::sh) settings.sh_order = static_cast<int>(build.integer("sh_order"));
  if (settings.storage == StorageKind::multires) {
    settings.multires_depth = static_cast<int>(build.integer("multires_depth"));
    settings.error_threshold = build.real("error_threshold");
    settings.multires_tree = build.text("multires_tree") == "per_sample" ? MultiresTree::per_sample : MultiresTree::shared;
  }
  if (settings.storage == StorageKind::shells) {
    settings.shell_count = static_cast<int>(build.integer("shell_count"));
    settings.shell_subdivision = static_cast<int>(build.integer("shell_subdivision"));
    settings.shell_spacing = build.text("shell_spacing") == "uniform" ? 0 : 1;
  }
  settings.precision = parse_precision(build.text("precision"));
  // auto: vector until resolve_orientation (lpi_build.cpp) takes it from the scene, in plan(),
  // build_dependencies() and knob_memory().
  settings.orientation_auto = build.text("orientation") == "auto";
  settings.orientation = build.text("orientation") == "paper" ? Orientation::paper : Orientation::vector;
  // The knob rules (static_info) refuse these before any work; a caller that bypassed them still stops here.
  const std::string one_cell = build.has("grid_resolution")  ? grid_one_cell_problem(build)
                               : build.has("multires_depth") ? multires_one_cell_problem(build)
                                                             : "";
  if (!one_cell.empty()) throw InputError("lpi: " + one_cell);
  settings.volume_radius = build.is_auto("volume_radius") ? 0.0 : build.real("volume_radius");
  settings.photons_per_sample = static_cast<uint64_t>(build.integer("photons_per_sample"));
  settings.seed = static_cast<uint64_t>(build.integer("seed"));
  return settings;
}


}  // namespace causticbench
