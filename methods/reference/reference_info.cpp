// The reference's declarations: its knobs, capabilities and counters (README.md's table is generated from them).
#include "methods/reference/reference.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/image_statistics.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "methods/common/photon_memory.h"
#include "methods/reference/reference_estimators.h"

namespace causticbench {

const MethodInfo& ReferenceMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "reference";
    m.paper = "T. Hachisuka, S. Ogaki, H. W. Jensen, \"Progressive Photon Mapping\", ACM TOG 27(5), 2008";
    m.summary = "Converged caustic irradiance per pixel, by crediting every photon the camera sees to its pixel's "
                "footprint (or by progressive photon mapping); stops on its own estimate of its total error, "
                "variance and bias, with the per-pixel map of it.";
    const ParamPhase render = ParamPhase::render;
    m.params = {
        ParamSpec::choice("estimator", "footprint", {"footprint", "ppm"},
                          "footprint: each photon the camera sees is credited to the pixel whose footprint holds it "
                          "(unbiased for the pixel's average E_c; docs/metrics.md); ppm: progressive photon mapping at "
                          "the pixel centres (biased near folds and foci by its radius)",
                          render),
        ParamSpec::choice("emission", "stratified", {"stratified", "random"},
                          "stratified: each pass's photons leave the lights at the points of a randomised Sobol sequence "
                          "(unbiased; evenly spread over where they aim, so a pixel's count varies less than at random), "
                          "the error measured from the spread of independent passes; random: independent draws, the "
                          "error from the photons' second moment",
                          render),
        ParamSpec::integer("photons_per_pass", 4000000, 1000, 1e9, "photons emitted per pass (ppm: split between the two halves)",
                           render),
        ParamSpec::real("target_error", 1e-3, 0.0, 1.0,
                        "stop when the estimated total error of the result (relMSE against the pixel's true E_c: "
                        "variance plus estimated squared bias) falls to this; 0: never",
                        render),
        ParamSpec::real("max_seconds", 600.0, 0.0, 1e7, "stop after this much wall time (0: no limit)", render),
        ParamSpec::integer("max_passes", 100000, 1, 1e9, "stop after this many passes", render),
        ParamSpec::integer("min_passes", 4, 1, 1e6, "never stop on the error target before this many passes", render),
        ParamSpec::real("alpha", 2.0 / 3.0, 0.01, 1.0, "fraction of new photons kept per pass (radius reduction)", render)
            .only_when("estimator", {"ppm"}),
        ParamSpec::real("initial_radius_pixels", 1.0, 0.05, 1000.0,
                        "initial gather radius in pixel footprints at each point", render)
            .only_when("estimator", {"ppm"}),
        ParamSpec::integer("max_bounces", 32, 1, 1000, "specular bounces before a photon path is cut", render),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of every random choice", render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = c.multiple_bounces = true;
    c.directional_light = c.point_light = c.environment_light = true;
    c.moving_light = c.moving_objects = c.occlusion = c.non_lambertian_receivers = true;
    c.notes = {{"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF"}};
    m.quick_knobs = {"photons_per_pass=20000", "max_passes=2", "target_error=0", "max_seconds=0"};
    m.budget_knob = "max_passes";
    // Per receiver pixel its point, the tally's two photon moments and three replicate sums and (ppm) both
    // halves' statistics, as memory_bytes() counts them: 153 bytes with the footprint tally, 225 with ppm;
    // the larger is declared.
    m.working_bytes_per_pixel = 225.0;
    m.counters = {counter_quantity("photons_emitted", "photons", "photons emitted over all passes"),
                  counter_quantity("photons_deposited", "photons", "photon hits on receivers over all passes"),
                  counter_quantity("photons_credited", "photons", "photon hits the camera sees on receiver pixels (footprint tally)"),
                  counter_quantity("passes", "passes", "progressive passes until the stop rule (stop_reason)")};
    return m;
  }();
  return info;
}


}  // namespace causticbench
