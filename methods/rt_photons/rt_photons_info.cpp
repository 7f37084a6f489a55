// rt_photons' declarations: its knobs with their phases and ranges, its capabilities and counters
// (methods/rt_photons/README.md's table is generated from them).
#include <fmt/format.h>

#include "methods/rt_photons/rt_photons.h"

namespace causticbench {

const MethodInfo& RtPhotonsMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "rt_photons";
    m.paper = "X. Yang, Y. Ouyang, \"Real-Time Ray Traced Caustics\", Ray Tracing Gems II, chapter 30, 2021 "
              "(adaptive anisotropic photon scattering)";
    m.summary = "Every frame, without precomputation: an emission map per light sends photons toward the specular "
                "objects, the scene's ray tracer carries them with their ray differentials through every reflection "
                "and refraction, and each is splatted over its own footprint (an ellipse from the differentials, a "
                "disc, or a fixed radius) onto the surface it lands on, normalised so that its flux is conserved.";
    m.params = {
        ParamSpec::integer("photons_per_frame", 262144, 16384, 16777216,
                           "photons emitted a frame over every light's emission map (2^14 to 2^24)", ParamPhase::frame),
        ParamSpec::integer("max_bounces", 16, 1, 64,
                           "specular interactions before a path is cut (its flux is counted lost; the glass bunny loses "
                           "9 % at 8)",
                           ParamPhase::frame),
        ParamSpec::integer("emission_resolution", 64, 4, 1024,
                           "texels a side of a light's emission map (a distant light's plane across its beam; each of a "
                           "point light's six cube faces)",
                           ParamPhase::frame),
        ParamSpec::integer("light_samples", 64, 1, 4096,
                           "emission maps an extended light is split into, redrawn every frame: directions from a sun's "
                           "disk, a Gaussian spot or an environment map (by the light's importance sampling), or points on "
                           "a sphere light; a parallel beam or a point light is one",
                           ParamPhase::frame)
            .unkeyed_at_default(),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the emission points and the photon paths", ParamPhase::frame),
        // Off by default: measured worse than uniform emission from the same budget on the turning bunny and
        // the water pool (yang2021_temporal.yaml), better at equal photons on the static glass sphere.
        ParamSpec::choice("adaptive", "off", {"on", "off"},
                          "adapt each emission texel's photon density after every frame so that its photons' "
                          "footprints approach target_footprint pixels (the chapter's contribution); off: uniform",
                          ParamPhase::frame),
        ParamSpec::real("target_footprint", 2.0, 0.5, 64.0,
                        "the kernel radius, in pixels, adaptive emission steers each texel's photons toward; the budget "
                        "caps the photons it may ask for",
                        ParamPhase::frame)
            .only_when("adaptive", {"on"}),
        ParamSpec::choice("footprint", "ray_differentials", {"ray_differentials", "ray_cone", "fixed"},
                          "a photon's kernel on the surface: the ellipse of its ray differentials, an isotropic disc of "
                          "the same area (ray_cone), or a fixed radius in pixels",
                          ParamPhase::render),
        ParamSpec::real("min_footprint", 1.0, 0.5, 64.0, "smallest kernel radius, in pixels at the hit", ParamPhase::render),
        ParamSpec::real("max_footprint", 32.0, 1.0, 1024.0, "largest kernel radius, in pixels at the hit",
                        ParamPhase::render),
        ParamSpec::real("fixed_footprint", 4.0, 0.5, 256.0, "the kernel radius of footprint: fixed, in pixels",
                        ParamPhase::render)
            .only_when("footprint", {"fixed"}),
        ParamSpec::real("temporal_alpha", 0.0, 0.0, 0.99,
                        "weight of the last frame's output, reprojected through the G-buffer's world positions, in "
                        "this frame's (0: off): less noise, more lag",
                        ParamPhase::render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = c.multiple_bounces = true;
    c.directional_light = c.point_light = c.environment_light = true;
    c.moving_light = c.moving_objects = c.occlusion = c.non_lambertian_receivers = true;
    c.notes = {{"environment_light", "light_samples directions drawn from the map each frame, each with its own emission map"},
               {"directional_light", "a sun's disk: light_samples directions across it each frame"},
               {"point_light", "a sphere light: light_samples points on its surface each frame"},
               {"moving_light", "photons are traced every frame"},
               {"moving_objects", "photons are traced every frame"}};
    // A kernel cannot be widened to more than it may be narrowed to: the clamp would be empty.
    m.knob_rules = {{{"min_footprint", "max_footprint"}, [](const ParamSet& knobs) {
                       return knobs.real("min_footprint") <= knobs.real("max_footprint")
                                  ? std::string()
                                  : fmt::format("min_footprint {} is above max_footprint {}: expected min_footprint <= "
                                                "max_footprint (the kernel's radius is clamped to [min, max])",
                                                knobs.real("min_footprint"), knobs.real("max_footprint"));
                     }}};
    m.quick_knobs = {"photons_per_frame=16384", "emission_resolution=16"};
    m.budget_knob = "photons_per_frame";
    m.counters = {counter_quantity("photons_emitted", "photons", "photons emitted this frame"),
                  counter_quantity("photons_landed", "photons", "photons that met a diffuse surface after a specular interaction"),
                  counter_quantity("photons_splatted", "photons", "landed photons that some pixel sees"),
                  counter_quantity("splatted_pixels", "pixels", "(photon, pixel) deposits of the last render"),
                  counter_quantity("footprints_widened", "photons", "kernels widened to min_footprint"),
                  counter_quantity("footprints_narrowed", "photons", "kernels narrowed to max_footprint"),
                  counter_quantity("active_texels", "texels", "emission texels that reach a specular object")};
    return m;
  }();
  return info;
}

}  // namespace causticbench
