// caustic_mapping's declarations: its knobs, capabilities and counters (README.md's table is generated
// from them). Every knob is a frame knob: the method precomputes nothing, and render() only looks up.
#include "methods/caustic_mapping/caustic_mapping.h"

namespace causticbench {

const MethodInfo& CausticMappingMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "caustic_mapping";
    m.paper = "M. A. Shah, J. Konttinen, S. Pattanaik, \"Caustics Mapping: An Image-Space Technique for Real-Time "
              "Caustics\", IEEE TVCG 13(2), 2007; variable splats: C. Wyman, C. Dachsbacher, \"Improving Image-Space "
              "Caustics via Variable-Sized Splatting\", Univ. of Iowa TR UICS-06-02, 2006";
    m.summary = "Per frame, per light and specular object: a photon buffer rendered from the light, each photon's "
                "receiver estimated in image space from the light's receiver map, splatted into a light-space caustic "
                "map that every receiver point reads like a shadow map. No precomputation.";
    m.params = {
        ParamSpec::integer("photon_resolution", 512, 2, 4096,
                           "photon buffer texels a side, over the object's silhouette from the light: one photon each",
                           ParamPhase::frame),
        ParamSpec::integer("caustic_map_resolution", 512, 2, 8192,
                           "receiver map and caustic map texels a side, over the receivers the object lights",
                           ParamPhase::frame),
        ParamSpec::choice("intersection", "image_space", {"image_space", "exact"},
                          "where a photon's ray meets the receivers: the paper's search over the receiver map, or a "
                          "real ray (to measure the estimate's error and cost)",
                          ParamPhase::frame),
        // Declared after intersection: the device has no exact rays, so setting backend: vulkan with
        // intersection: exact is refused before any work starts.
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "where the frame is rendered: the CPU (its ray tracer renders the light views), or a "
                          "Vulkan raster pipeline (the light views rasterised from the scene's triangles, analytic "
                          "shapes tessellated; photons; sprites blended into the caustic map; lookup); the CPU "
                          "fits the light views for both",
                          ParamPhase::frame)
            .only_when("intersection", {"image_space"})
            .unkeyed_at_default(),
        ParamSpec::integer("search_iterations", 5, 0, 64,
                           "steps of the image-space search after its start at the photon's own texel",
                           ParamPhase::frame)
            .only_when("intersection", {"image_space"}),
        ParamSpec::choice("hit_position", "plane", {"plane", "texel"},
                          "the search's hit: where the ray meets the found receiver's plane, or that receiver itself "
                          "(the paper's, which snaps photons to the map's texels)",
                          ParamPhase::frame)
            .only_when("intersection", {"image_space"}),
        ParamSpec::choice("refraction", "auto", {"auto", "two_interface", "one_interface"},
                          "glass: out through the back by Wyman's image-space approximation, one refraction (a water "
                          "surface over its floor), or auto: two where the light sees the object's back, one where not",
                          ParamPhase::frame),
        ParamSpec::choice("splat", "variable", {"variable", "gaussian", "point"},
                          "photon splat: radius from the local photon density (Wyman & Dachsbacher), a fixed "
                          "Gaussian, or one texel",
                          ParamPhase::frame),
        ParamSpec::real("splat_radius", 1.5, 0.5, 64.0, "gaussian splat radius, caustic-map texels", ParamPhase::frame)
            .only_when("splat", {"gaussian"}),
        ParamSpec::real("splat_photons", 16.0, 1.0, 10000.0,
                        "variable splats: photons a splat holds at the local density (its k-nearest radius)",
                        ParamPhase::frame)
            .only_when("splat", {"variable"}),
        ParamSpec::real("max_splat_radius", 16.0, 0.5, 256.0, "variable splats: largest radius, caustic-map texels",
                        ParamPhase::frame)
            .only_when("splat", {"variable"}),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = true;
    c.directional_light = c.point_light = true;
    c.moving_light = c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {{"refraction", "two interfaces of one object by Wyman's image-space approximation (refraction: "
                              "two_interface), or one (one_interface); glass's Fresnel reflection is not followed"},
               {"multiple_bounces", "one object at a time: light between specular objects is not followed"},
               {"environment_light", "no single light view: an environment light is skipped and named in the record"},
               {"moving_light", "everything is rendered again every frame"},
               {"moving_objects", "everything is rendered again every frame"},
               {"occlusion", "light blocked between the light and the object is (the photon buffer's depth test), "
                             "but not between the object and its receivers: the image-space search takes the receiver "
                             "the light sees for the one the ray meets and puts the light behind an occluder (relMSE 34 at "
                             "5 search steps, 54 at 20, on the capability case); intersection: exact follows the ray, "
                             "but the caustic map still holds light only where the light sees a receiver, so light in "
                             "an occluder's shadow is dropped (relMSE 0.11, energy 0.74 there; both measured by "
                             "configs/experiments/capabilities_knobs.yaml)"},
               {"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF"}};
    m.quick_knobs = {"photon_resolution=64", "caustic_map_resolution=64"};
    m.counters = {counter_quantity("photons", "photons", "photon-buffer texels on the specular objects, every pass"),
                  counter_quantity("photons_landed", "photons", "photons splatted into a caustic map"),
                  counter_quantity("search_failures", "photons",
                                   "photons whose receiver search left the light view, found no receiver or did not converge"),
                  counter_quantity("receiver_map_reads", "reads", "receiver-map reads of the image-space searches")};
    return m;
  }();
  return info;
}

}  // namespace causticbench
