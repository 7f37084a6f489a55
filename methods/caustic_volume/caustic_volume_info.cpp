// caustic_volume's declarations: its knobs, capabilities and counters (README.md's table is generated from
// them). The volumes are built per frame (frame knobs); how their light is spread is a render knob, so
// that runs differing only in it share the volumes.
#include "methods/caustic_volume/caustic_volume.h"

namespace causticbench {

const MethodInfo& CausticVolumeMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "caustic_volume";
    m.paper = "C. Ernst, T. Akenine-Möller, H. W. Jensen, \"Interactive rendering of caustics using interpolated "
              "warped volumes\", Graphics Interface 2005";
    m.summary = "Per frame, every lit triangle of a specular surface and its three reflected or refracted vertex rays "
                "bound a warped volume; every receiver point inside gets that beam's light, at the intensity of its "
                "spread or focus there, interpolated from per-vertex wavefront densities. No precomputation.";
    m.params = {
        ParamSpec::integer("tessellation", 64, 3, 4096,
                           "quads around an analytic shape's axis (a sphere 64 x 32, a ring's wall 64 x 8: Ernst et "
                           "al.'s 2 x 64 x 8 triangles); a box's or prism's triangles are cut (tessellation / 4)^2 each; "
                           "other meshes keep their own triangles",
                           ParamPhase::frame),
        ParamSpec::real("max_distance", 0.0, 1e-6, 1e9,
                        "the far cap: how far along its vertex rays a volume reaches, scene units; auto: per volume, "
                        "where all its rays have left the box that holds the receivers (none lies beyond)",
                        ParamPhase::frame)
            .auto_by_default(),
        // Added after the first experiments shipped; its default changes none of them (they refract only
        // at a water surface, where auto is one interface): kept out of their keys.
        ParamSpec::choice("refraction", "auto", {"auto", "one_interface", "through_object"},
                          "glass: one interface, the receivers in the medium (the paper's water surface over a "
                          "pool floor), or each vertex ray followed through the object to where it leaves, its "
                          "total internal reflections included (beyond the paper); auto: through where the "
                          "refracted ray meets its object again, one interface where it does not",
                          ParamPhase::frame)
            .unkeyed_at_default(),
        ParamSpec::choice("intensity", "interpolated", {"interpolated", "constant"},
                          "the light across a cross-section: each vertex's wavefront density as it spreads or "
                          "focuses, interpolated (the paper's), or the triangle's flux spread evenly (Nishita & "
                          "Nakamae, Iwasaki et al.: faceted)",
                          ParamPhase::render),
        ParamSpec::choice("occlusion", "none", {"none", "shadow_rays"},
                          "light inside a volume: reaches every receiver point in it (the paper's, like a shadow "
                          "volume without its shadow), or only those whose shadow ray back to where the light left "
                          "the surface is clear (beyond the paper; one ray a point and sheet)",
                          ParamPhase::render)
            .unkeyed_at_default(),
        // Declared after occlusion: the device traces no shadow rays, so backend: vulkan with occlusion:
        // shadow_rays is refused before any work starts. Added after runs were recorded: cpu stays out of
        // their keys.
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "where the receiver points are tested: the CPU (each volume against the points of its "
                          "footprint's rows), or a Vulkan raster pipeline (the footprints rasterised over the image, "
                          "each fragment's point tested exactly in float, the light blended additively); the volumes "
                          "are the CPU's for both",
                          ParamPhase::render)
            .only_when("occlusion", {"none"})
            .unkeyed_at_default(),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = true;
    c.directional_light = c.point_light = true;
    c.moving_light = c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {{"refraction", "one interface (the paper's water surface over a pool floor: the receivers lie in "
                              "the medium) or, for a solid, each vertex ray through the object to where it leaves "
                              "(refraction: auto picks per vertex); volumes whose rays leave differently are torn, "
                              "dropped and counted"},
               {"multiple_bounces", "one interface per volume: light between specular objects is not followed"},
               {"environment_light", "no single direction per vertex: an environment light is skipped and named in "
                                     "the record"},
               {"moving_light", "everything is built again every frame"},
               {"moving_objects", "everything is built again every frame"},
               {"occlusion", "light reaching the specular triangle is tested (a vertex that does not see the light "
                             "brings none), light inside a volume is not by default: a receiver behind an occluder "
                             "inside the beam is lit (measured relMSE 58, energy 1.39, on the capability case); the "
                             "render knob occlusion: shadow_rays tests each point's light against the scene"},
               {"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF"}};
    m.quick_knobs = {"tessellation=16"};
    m.counters = {counter_quantity("volumes", "volumes", "caustic volumes built (lit triangles), every light and object"),
                  counter_quantity("volume_point_tests", "tests",
                                   "receiver points tested against a volume (a cubic solved): the fill cost"),
                  counter_quantity("volume_hits", "tests", "tests that found the receiver point inside the volume"),
                  counter_quantity("shadow_rays", "rays", "occlusion: shadow_rays: rays traced from receiver points")};
    return m;
  }();
  return info;
}

}  // namespace causticbench
