// pinhole's declarations: its knobs with their phases and ranges, its capabilities and counters
// (Wand & Strasser 2003; methods/pinhole/README.md is generated from them).
#include "methods/pinhole/pinhole.h"

#include <fmt/format.h>

#include "core/optics.h"
#include "core/parallel.h"
#include "gpu/cube_filter_check.h"
#include "methods/common/gpu_arrays.h"
#include "methods/pinhole/cube_filter.h"
#include "methods/pinhole/reflection_lanes.h"
#include "methods/pinhole/texel_fetch.h"
#include "methods/pinhole/throughput.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

const MethodInfo& PinholeMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "pinhole";
    m.paper = "M. Wand, W. Strasser, \"Real-Time Caustics\", Computer Graphics Forum 22(3), 2003";
    m.summary = "Samples the reflector every frame; each sample projects the light's environment map onto the "
                "receivers like a pinhole camera, optionally with curvature-based anisotropic filtering.";
    const ParamPhase build = ParamPhase::build, frame = ParamPhase::frame, render = ParamPhase::render;
    m.params = {
        ParamSpec::integer("samples", 1000, 1, 1e7, "target number of reflector samples (pinhole cameras) per frame", frame),
        ParamSpec::choice("sampling", "neighborhood", {"random", "grid", "quantized_grid", "neighborhood"},
                          "stratification of the samples (Section 3.2)", frame),
        ParamSpec::choice("filtering", "anisotropic", {"none", "isotropic", "anisotropic"},
                          "resampling filter of the light lookups from differential point samples (Section 3.3); the "
                          "paper's method is the anisotropic one, none its unfiltered Figs. 4 and 5",
                          build),
        ParamSpec::choice("filter_implementation", "own", {"own", "oiio", "hardware"},
                          "own: the method's footprint filter on a mip-mapped cube map, the same on both backends; "
                          "oiio: OpenImageIO's on a lat-long texture (cpu only); hardware: the device's textureGrad "
                          "(vulkan only)", build)
            .only_when("filtering", {"isotropic", "anisotropic"}),
        ParamSpec::choice("interaction", "auto", {"auto", "reflect", "refract"},
                          "auto: each object by its material (glass refracts, a mirror or a diffuse+mirror surface "
                          "reflects); reflect: one mirror reflection at every specular object, glass included (its "
                          "Fresnel reflection); refract: one refraction at glass (the variant Section 5 names)",
                          build),
        ParamSpec::integer("environment_resolution", 256, 4, 4096, "cube map face size of the light map (paper: 256)", frame),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the reflector sampling", frame),
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "cpu (multithreaded, SIMD) or vulkan (compute shader; lavapipe without a GPU)", build),
        ParamSpec::real("epsilon", -1.0, 0.0, 1e6,
                        "added to the squared distance against the singularity; -1: the squared sample spacing A/N", render)
            .or_special(-1.0),
        ParamSpec::boolean("attenuation", true, "cosines over squared distance; false reproduces Fig. 5", render),
        ParamSpec::boolean("fresnel", true, "angle-dependent reflectance (conductor or dielectric Fresnel)", render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = true;
    c.refraction = true;
    c.multiple_bounces = false;
    c.directional_light = c.environment_light = true;
    // Measured in tests/test_capabilities.cpp: a point light near the reflector, taken as distant from its
    // centre, lights parts of it the light cannot reach (energy 3.4x the reference's there).
    c.point_light = false;
    c.moving_light = c.moving_objects = true;
    c.occlusion = false;
    // E_c is irradiance, which does not depend on the receiver's BRDF (measured equal on a glossy floor).
    c.non_lambertian_receivers = true;
    // A closed glass object (two interfaces) is beyond the paper's single refraction: measured on the glass
    // sphere of configs/scenes/capabilities/glass/ (README, "Refraction: one interface").
    c.notes = {{"refraction", "a single refraction (interaction: refract), e.g. a water surface over a pool floor; the "
                              "receiver is taken to lie in the glass, so a closed object's exit interface is not "
                              "modelled (a glass sphere over a floor: energy 1.31, what one interface gives)"},
               {"point_light", "approximated as distant from the reflectors' centre, as the paper does: right for a light "
                               "far from the reflector, measurably wrong for one near it (Liu 2008 Table 1 agrees)"},
               {"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF; each sample's "
                                            "light direction is known, so a glossy BRDF could be shaded (Liu 2008 "
                                            "Table 1 marks pinhole so)"},
               {"occlusion", "no visibility between reflector samples and receivers beyond back-face culling"},
               {"multiple_bounces", "one specular interaction only"}};
    m.quick_knobs = {"samples=64", "environment_resolution=32"};
    m.budget_knob = "samples";
    m.counters = {counter_quantity("samples", "samples", "reflector samples (pinholes) per frame"),
                  counter_quantity("cube_map_texels", "texels", "texels of the light's cube map"),
                  counter_quantity("sample_evaluations", "evaluations",
                                   "receiver pixels x samples of the last frame (the pairs the kernel accounts for)")};
    return m;
  }();
  return info;
}

}  // namespace causticbench
