// photon_map's declarations: its knobs, capabilities and counters (README.md's table is generated from them).
#include "methods/photon_map/photon_map.h"

#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nanoflann.hpp>

#include "core/files.h"
#include "core/parallel.h"
#include "core/scene_description.h"
#include "methods/common/photon_memory.h"

namespace causticbench {

const MethodInfo& PhotonMapMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "photon_map";
    m.paper = "H. W. Jensen, \"Global Illumination Using Photon Maps\", EGWR 1996 (caustic photon map, cone filter)";
    m.summary = "Traces a fixed number of caustic photons (every frame; once, cached, for a static scene) into a kd-tree (nanoflann) and estimates "
                "irradiance from the k nearest photons with a cone filter.";
    m.params = {
        ParamSpec::integer("photons", 200000, 1, 1e9, "caustic photons emitted per frame", ParamPhase::build),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the photon paths", ParamPhase::build),
        ParamSpec::integer("k", 50, 1, 10000, "photons in each density estimate (nearest neighbours)", ParamPhase::render),
        ParamSpec::real("max_radius", 0.1, 1e-9, 1e9,
                        "largest gather radius, scene units; auto: 8 times each pixel's footprint on its surface",
                        ParamPhase::render)
            .auto_by_default(),
        ParamSpec::real("cone_filter_k", 1.1, 1.0, 100.0, "cone filter constant k >= 1 (Jensen): weight 1 - d / (k r)",
                        ParamPhase::render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = c.multiple_bounces = true;
    c.directional_light = c.point_light = c.environment_light = true;
    c.moving_light = c.moving_objects = c.occlusion = c.non_lambertian_receivers = true;
    c.notes = {{"moving_light", "photons are retraced every frame"},
               {"moving_objects", "photons are retraced every frame; a static scene's are traced once and cached"}};
    m.quick_knobs = {"photons=20000"};
    m.budget_knob = "photons";
    m.counters = {counter_quantity("photons_emitted", "photons", "photons emitted toward the specular objects"),
                  counter_quantity("photons_stored", "photons", "caustic photons stored in the map")};
    return m;
  }();
  return info;
}


}  // namespace causticbench
