// prt's declarations: its knobs with their phases and ranges, its capabilities and counters
// (methods/prt/README.md's table is generated from them), and the transfer settings the knobs give.
#include "methods/prt/prt.h"

namespace causticbench {

const MethodInfo& PrtMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "prt";
    m.paper = "P.-P. Sloan, J. Kautz, J. Snyder, \"Precomputed Radiance Transfer for Real-Time Rendering in Dynamic, "
              "Low-Frequency Lighting Environments\", SIGGRAPH 2002 (neighbourhood transfer)";
    m.summary = "Precomputes, on a grid around each specular object, a matrix from the source lighting's spherical "
                "harmonics to the caustic radiance arriving in each cell (photon tracks from source directions over "
                "the sphere); per frame it projects the lighting once, multiplies it into every cell and gives each "
                "receiver point its clamped-cosine sum. Environment maps are its strength, sharp lights blur and ring.";
    m.params = {
        ParamSpec::integer("sh_order", 5, 2, kMaxBands,
                           "bands of the spherical harmonics (the paper's 5: 25 coefficients a direction, 625 matrix "
                           "entries a cell and colour); not lpi's sh_order, which counts the highest degree",
                           ParamPhase::build),
        ParamSpec::integer("grid_resolution", 32, 2, 128, "cells along each axis of the grid over the ball",
                           ParamPhase::build),
        ParamSpec::real("volume_radius", 3.0, 0.01, 1000.0,
                        "radius of the ball the grid covers, in bounding radii of the object; auto: the smallest ball "
                        "holding 98 % of where the object's light first meets a receiver in the rendered frames (probe "
                        "photons at prepare), times 1.1, capped where the grid stops resolving the object",
                        ParamPhase::build)
            .auto_by_default(),
        ParamSpec::integer("source_directions", 256, 4, 65536,
                           "directions over the whole sphere the transfer is shot from (spherical Fibonacci, equal areas)",
                           ParamPhase::build),
        ParamSpec::integer("photons_per_direction", 20000, 1, 4e9, "photons shot at the object per source direction",
                           ParamPhase::build),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the photon paths", ParamPhase::build),
        // Added after prt's first runs were recorded: float32 (what they did) stays out of their keys.
        ParamSpec::choice("precision", "float32", {"float32", "float16"},
                          "stored matrix entries: float32, or float16 (half the memory and half the bytes the frame's "
                          "product reads, about 3 significant digits an entry)",
                          ParamPhase::build)
            .unkeyed_at_default(),
        ParamSpec::choice("window", "none", {"none", "hanning", "lanczos"},
                          "a window on the lighting's bands (beyond the paper): none, or hanning / lanczos, which trade "
                          "the ringing of a sharp light for blur and keep its total",
                          ParamPhase::frame),
        // Added after prt's first runs were recorded: cpu stays out of their keys.
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "where the frame is computed: the CPU (l = M L per cell, then the lookup per receiver "
                          "point), or Vulkan compute shaders (the matrices uploaded once a build, both steps on the "
                          "device); the lighting is projected on the CPU for both",
                          ParamPhase::frame)
            .unkeyed_at_default(),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = true;
    c.directional_light = c.environment_light = true;
    c.moving_light = c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {{"reflection", "band-limited: a sharp reflected light is blurred to sh_order bands and rings"},
               {"refraction", "inside the object as outside it: every path through the object alone"},
               {"multiple_bounces", "the transfer holds every bounce within the object, none between objects"},
               {"point_light", "taken as a directional light from the object's centre with the irradiance there (as lpi "
                               "and csl): a near light's fan is several times too bright (measured energy 3.4 on the "
                               "capability case)"},
               {"environment_light", "projected on the harmonics once per pose of the map, turned with the object"},
               {"moving_light", "the lighting is projected every frame; nothing is rebuilt"},
               {"moving_objects", "the field moves and turns with its object (its build space); nothing is rebuilt"},
               {"occlusion", "the transfer is of the object alone: another object in the way is not in it (Liu 2008 "
                             "marks PRT's occluded caustic light: the object's own shadowing, which it holds)"},
               {"non_lambertian_receivers", "E_c is irradiance, whatever the receiver's BRDF (a glossy lobe would "
                                            "replace the clamped cosine)"}};
    m.quick_knobs = {"sh_order=3", "grid_resolution=16", "source_directions=32", "photons_per_direction=4000"};
    m.counters = {counter_quantity("cells", "cells", "transfer cells over all objects"),
                  counter_quantity("photons_emitted", "photons", "photons shot over all source directions and objects"),
                  counter_quantity("precompute_seconds", "s", "precomputation time, all objects", QuantityKind::timing),
                  counter_quantity("bytes_per_cell", "bytes", "a cell's transfer matrices (3 x sh_order^4 entries)",
                                   QuantityKind::size),
                  counter_quantity("receiver_points", "points",
                                   "receiver points times objects evaluated in the last frame (divided by render_ms: "
                                   "the evaluation rate)")};
    return m;
  }();
  return info;
}

prt::TransferSettings prt::transfer_settings(const ParamSet& build) {
  TransferSettings settings;
  settings.bands = static_cast<int>(build.integer("sh_order"));
  settings.grid_resolution = static_cast<int>(build.integer("grid_resolution"));
  settings.volume_radius = build.is_auto("volume_radius") ? 0.0 : build.real("volume_radius");
  settings.source_directions = static_cast<int>(build.integer("source_directions"));
  settings.photons_per_direction = static_cast<uint64_t>(build.integer("photons_per_direction"));
  settings.seed = static_cast<uint64_t>(build.integer("seed"));
  settings.half = build.has("precision") && build.text("precision") == "float16";
  return settings;
}

}  // namespace causticbench
