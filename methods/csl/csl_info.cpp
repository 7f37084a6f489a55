// csl's declaration (knobs, capabilities, counters) and the settings its knobs make, apart from the
// lifecycle in csl.cpp.
#include <cmath>

#include "methods/csl/csl.h"

namespace causticbench {

using namespace csl;

const MethodInfo& CslMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "csl";
    m.paper = "X. Liu, Z. Dong, H. Bao, Q. Peng, \"Caustic spot light for rendering caustics\", The Visual Computer 24, 2008";
    m.summary = "Traces a grid of parallel light rays through each specular object once, clusters the rays that leave it "
                "into bundles and fits each bundle with a caustic spot light (a light plane whose rays focus along its "
                "axis, f(r) = alpha / (1 + beta r), with an intensity image); per frame every receiver point sums the "
                "spot lights' rays that reach it, found in closed form.";
    m.params = {
        ParamSpec::integer("rays_per_side", 1280, 2, 8192,
                           "parallel rays per side of the square over the object's bounding sphere (the paper: 1280)",
                           ParamPhase::build),
        ParamSpec::real("min_energy", 0.01, 0.0, 1.0,
                        "a reflected or refracted branch is dropped below this fraction of its ray's starting energy",
                        ParamPhase::build),
        ParamSpec::integer("raster_resolution", 64, 4, 512,
                           "cells along each axis of the grid the rays' lines are rasterised into (Section 3.1.1, step 1)",
                           ParamPhase::build),
        ParamSpec::real("raster_extent", 4.0, 1.0, 100.0,
                        "half the side of that grid's cube, in bounding radii of the object (the extended bounding volume)",
                        ParamPhase::build),
        ParamSpec::real("distance_threshold", 0.3, 1e-6, 100.0,
                        "largest distance between a ray's line and a bundle's axis, in bounding radii", ParamPhase::build),
        ParamSpec::real("angle_threshold", 90.0, 0.0, 90.0,
                        "largest angle between a ray and a bundle's axis, degrees (the paper's bundle definition: 90)",
                        ParamPhase::build),
        ParamSpec::real("energy_coverage", 0.95, 0.0, 1.0,
                        "spot lights are made until this fraction of the rays' energy is covered (the paper: 0.95)",
                        ParamPhase::build),
        ParamSpec::integer("max_csls", 64, 1, 4096, "spot lights per object and light direction at most", ParamPhase::build),
        ParamSpec::integer("fit_rays", 1024, 1, 1e7,
                           "rays of a bundle that Eq. 5 sums over in the fit (evenly strided; all of them go into the image)",
                           ParamPhase::build),
        ParamSpec::real("fit_tolerance", 0.3, 0.0, 2.0,
                        "a bundle ray whose direction differs from its spot light ray's by more (|d - e|, about radians) "
                        "is dismissed from the bundle",
                        ParamPhase::build),
        ParamSpec::real("splat_scale", 3.0, 0.1, 100.0,
                        "delta, the rays' splat radius, in ray spacings: their spacing on the object (the paper: 3 of them) or, where wider, "
                        "on the light plane", ParamPhase::build),
        ParamSpec::choice("image_size", "auto", {"auto", "128", "256", "512"},
                          "texels per side of the intensity images; auto: 128, 256 or 512 per spot light by the size of "
                          "its image on the light plane, as the paper chose",
                          ParamPhase::build),
        ParamSpec::choice("precision", "uint16", {"uint16", "float32"},
                          "intensity image texels: 16-bit integers with a scale per image (the paper) or floats",
                          ParamPhase::build),
        ParamSpec::choice("light_samples", "auto", {"auto", "all"},
                          "auto: when no light's direction in an object's frame changes over the rendered frames, one "
                          "static set per direction; otherwise the sets of the icosahedron facets those directions fall "
                          "in (Section 4); all: every facet of the icosahedron",
                          ParamPhase::build),
        ParamSpec::integer("light_subdivision", 2, 0, 4,
                           "subdivisions of the icosahedron of light directions (the paper: 2, 162 directions)",
                           ParamPhase::build),
        ParamSpec::integer("tracking_steps", 20, 1, 1000,
                           "steps in which the light turns from one direction to its neighbour while the spot lights' "
                           "axes are tracked (Section 4.2; the paper: 20)",
                           ParamPhase::build),
        ParamSpec::integer("tracking_rays_per_side", 128, 2, 8192,
                           "parallel rays per side of the grid traced at each tracking step", ParamPhase::build),
        ParamSpec::real("match_distance", 1.0, 0.0, 100.0,
                        "largest axis distance (Section 4.2) of a matched pair, in bounding radii; farther spot lights "
                        "get black partners",
                        ParamPhase::build),
        ParamSpec::choice("interpolation", "barycentric", {"barycentric", "nearest"},
                          "dynamic light: the triples of the facet the light falls in, interpolated with its "
                          "barycentric weights (Section 4.1), or the set of the nearest direction (jumps)",
                          ParamPhase::frame),
        ParamSpec::choice("focus_interpolation", "curvature", {"curvature", "distance"},
                          "interpolate kappa = 1 / alpha (curvature) or alpha itself (distance, the paper; falls back "
                          "to curvature where a corner is collimated or diverging)",
                          ParamPhase::frame),
        ParamSpec::choice("intensity_correction", "on", {"on", "off"},
                          "divide each ray's intensity by the area ratio of Eq. 4 (Fig. 6 compares on and off)",
                          ParamPhase::render),
        ParamSpec::choice("on_axis", "integrate", {"integrate", "epsilon"},
                          "points whose footprint reaches the axis: the flux through that disk over its area (integrate), "
                          "or moved out to axis_epsilon from it (the paper's epsilon)",
                          ParamPhase::render),
        // A render knob, unlike pinhole's build-phase backend: the spot lights (the costly build) and
        // their interpolation do not depend on it, so both backends share one build and one update.
        // Added after csl's runs were recorded, so cpu (what they did) is left out of their keys.
        ParamSpec::choice("backend", "cpu", {"cpu", "vulkan"},
                          "cpu (multithreaded) or vulkan (a compute shader evaluates the frame's spot lights in float; "
                          "lavapipe without a GPU)",
                          ParamPhase::render)
            .unkeyed_at_default(),
        ParamSpec::choice("occlusion", "none", {"none", "shadow_rays"},
                          "none (the paper); shadow_rays: each contributing ray's light is kept only when the path from "
                          "the receiver back along it meets no other object before the caustic object (Embree, one ray "
                          "per contributing spot light ray; the cpu backend only)",
                          ParamPhase::render)
            .only_when("backend", {"cpu"}),
        // Added after csl's runs were recorded; neither default changes the image (the cull is exact, the
        // double lanes agree with the scalar evaluation to rounding), so they are left out of the run key.
        ParamSpec::choice("cull", "on", {"on", "off"},
                          "on: each spot light is evaluated only at the receivers its rays' volume may reach (a "
                          "conservative bound per 8 x 8 pixels and per 8 receivers; the image is the same bit for bit); "
                          "off: every receiver and spot light (the cpu backend)",
                          ParamPhase::render)
            .only_when("backend", {"cpu"})
            .unkeyed_at_default(),
        ParamSpec::choice("lanes", "vector", {"vector", "float", "scalar"},
                          "vector: the geometry of Eqs. 2 to 4 for 8 receivers at a time in double SIMD lanes (AVX2 or "
                          "SSE2), then the image lookups of the rays found (8 at a time, gathered, from a one-channel "
                          "image); float: the same geometry in float lanes, twice as wide, to the Vulkan kernel's "
                          "tolerance; scalar: one receiver at a time; shadow_rays always run scalar (the cpu backend)",
                          ParamPhase::render)
            .only_when("backend", {"cpu"})
            .unkeyed_at_default(),
        ParamSpec::real("axis_epsilon", 1e-4, 1e-9, 1.0, "on_axis: epsilon: the distance, in bounding radii",
                        ParamPhase::render)
            .only_when("on_axis", {"epsilon"}),
    };
    Capabilities& c = m.capabilities;
    c.refraction = true;
    c.directional_light = true;
    c.moving_light = true;
    c.moving_objects = true;
    c.non_lambertian_receivers = true;
    c.notes = {
        {"reflection", "the reflection of a convex mirror (a hemisphere of directions) is cut into cones of spot lights "
                       "whose seams and coarse images show: measured on the capability ellipsoid at 512 rays a side, "
                       "energy 0.79 and relMSE 4.3; the paper's objects are glass"},
        {"multiple_bounces", "any number within one object (the ray tree splits at every glass surface); none between "
                             "objects: each object's spot lights are made from that object alone"},
        {"point_light", "taken as a directional light from the object's centre, with the irradiance there"},
        {"environment_light", "refused (Liu 2008, Table 1)"},
        {"moving_light", "spot light sets at the directions of a subdivided icosahedron, matched and interpolated "
                         "per frame (Section 4); only the facets the rendered frames need are built"},
        {"moving_objects", "the spot lights move and turn with their object; an object that turns under a fixed light "
                           "changes the light's direction in its frame, which the dynamic sets follow"},
        {"occlusion", "by default the caustic light reaches receivers behind other objects, as in the paper; the render "
                      "knob occlusion: shadow_rays tests each contributing ray against the scene"},
        {"non_lambertian_receivers", "E_c is irradiance, whatever the receiver's BRDF; the spot lights know each ray's "
                                     "direction, so view-dependent shading could use it"},
    };
    m.quick_knobs = {"rays_per_side=48", "image_size=128"};
    m.counters = {counter_quantity("spot_lights", "lights", "caustic spot lights over all objects and light directions"),
                  counter_quantity("caustic_rays", "rays", "caustic object rays that left the objects (all directions)"),
                  counter_quantity("csl_evaluations", "evaluations",
                                   "receiver point and spot light pairs evaluated in the last frame, after the cull (the "
                                   "Vulkan backend: every pair)"),
                  counter_quantity("image_bytes", "bytes", "intensity images, all spot lights", QuantityKind::size),
                  counter_quantity("light_directions", "directions", "light directions with a spot light set, all objects"),
                  counter_quantity("spot_lights_per_direction", "lights",
                                   "spot lights per light direction, mean over all objects' sets (Liu 2008, Table 2: CSLs per light)"),
                  counter_quantity("triples_per_facet", "triples",
                                   "CSL triples per icosahedron facet, mean over the facets built (0 for static sets)"),
                  counter_quantity("interpolated_spot_lights", "lights",
                                   "spot lights interpolated from triples for the last frame")};
    return m;
  }();
  return info;
}

GenerateSettings csl::generate_settings(const ParamSet& build, const BoundingSphere& bounds, double ray_spacing) {
  GenerateSettings settings;
  const double radius = bounds.radius;
  settings.bundle.raster_resolution = static_cast<int>(build.integer("raster_resolution"));
  settings.bundle.raster_half_size = build.real("raster_extent") * radius;
  settings.bundle.distance_threshold = build.real("distance_threshold") * radius;
  settings.bundle.cos_angle_threshold = std::cos(build.real("angle_threshold") * kPiDouble / 180.0);
  settings.fit.reach = 4.0 * 2.0 * radius;  // four times the bounding box's size
  settings.fit.max_rays = static_cast<int>(build.integer("fit_rays"));
  settings.fit.plane_range = 2.0 * radius;  // one object diameter behind the rays' origins
  settings.splat.spacing = ray_spacing;
  settings.splat.splat_scale = build.real("splat_scale");
  settings.splat.image_size = build.text("image_size") == "auto" ? 0 : std::stoi(build.text("image_size"));
  settings.splat.precision = build.text("precision") == "uint16" ? IntensityImage::Precision::uint16
                                                                 : IntensityImage::Precision::float32;
  settings.energy_coverage = build.real("energy_coverage");
  settings.max_lights = static_cast<int>(build.integer("max_csls"));
  settings.fit_tolerance = build.real("fit_tolerance");
  return settings;
}

EvaluationSettings csl::evaluation_settings(const ParamSet& render, const BoundingSphere& bounds) {
  EvaluationSettings settings;
  settings.intensity_correction = render.text("intensity_correction") == "on";
  settings.on_axis = render.text("on_axis") == "integrate" ? OnAxis::integrate : OnAxis::epsilon;
  if (settings.on_axis == OnAxis::epsilon) settings.axis_epsilon = render.real("axis_epsilon") * bounds.radius;
  return settings;
}

}  // namespace causticbench

namespace causticbench {

TrackingSettings csl::tracking_settings(const ParamSet& build, const BoundingSphere& bounds) {
  TrackingSettings settings;
  settings.steps = static_cast<int>(build.integer("tracking_steps"));
  settings.rays_per_side = static_cast<int>(build.integer("tracking_rays_per_side"));
  settings.tree.min_energy = static_cast<float>(build.real("min_energy"));
  settings.bundle = generate_settings(build, bounds, 1.0).bundle;
  // A tracking step turns the light by a twentieth of an edge, so an axis moves little; and the axes
  // of a complex object's bundles may orbit without converging (methods/csl/bundles.cpp: the bunny's
  // at the former distance_threshold 0.1), which at the 100-step cap of bundle extraction made
  // tracking the bunny's 480 edges cost hours. 20 steps a
  // tracking step bound it.
  settings.bundle.max_iterations = 20;
  settings.match_distance = build.real("match_distance") * bounds.radius;
  return settings;
}

}  // namespace causticbench
