// The scene pinhole's tests render most: a mirror sphere above a floor, seen from above. One
// reflection and no occlusion of the reflected light, so the pinhole method converges to the
// reference. Shared by methods/pinhole/tests/test_pinhole.cpp and methods/pinhole/tests/test_pinhole_filter.cpp.
#pragma once

#include <string>

#include <fmt/format.h>

namespace causticbench::testing {

// A wide light from above (a Gaussian spot of 0.2 sr) unless `lights` (a YAML list) says otherwise.
inline std::string pinhole_mirror_sphere(
    const std::string& lights =
        "[{type: environment, procedural: gaussian_spot, direction: [0.4, -1, 0], irradiance: 1, solid_angle_sr: 0.2}]",
    int resolution = 32) {
  return fmt::format(R"(
camera: {{type: orthographic, position: [0, 5, 0.01], look_at: [0, 0, 0], view_height: 4, resolution: [{0}, {0}]}}
lights: {1}
objects:
  - shape: {{type: quad, size: [8, 8]}}
    material: {{type: diffuse}}
  - shape: {{type: sphere, radius: 0.5}}
    material: {{type: mirror, reflectance: 0.9}}
    transform: {{translate: [0, 1.2, 0]}}
)",
                     resolution, lights);
}

}  // namespace causticbench::testing
