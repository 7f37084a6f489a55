// The flat mirror of caustic_mapping's tests (test_caustic_mapping.cpp, test_caustic_mapping_vulkan.cpp):
// a scene whose caustic is known in closed form.
#pragma once

namespace causticbench::testing {

// A 0.6 x 0.6 mirror (reflectance 0.9) 1.5 above the floor, under a sun of irradiance 2 travelling at 45
// degrees down towards +x, turned (112.5 degrees about z) so that it reflects the light straight down: the
// beam keeps its cross-section, the mirror's area times the cosine to the light (0.383), and lights a
// 0.6 x 0.230 rectangle of the floor with E = 2 x 0.9 = 1.8 exactly. (Under a horizontal sun the light
// would see the floor edge-on, and caustics mapping, which finds receivers in the light's view, none.)
// An orthographic camera under the mirror looks straight down, so that a pixel's area on the floor is
// exactly (1.2 / 96)^2 and the pixels' sum is the flux.
inline const char* const kFlatMirror = R"(
camera: {type: orthographic, position: [1.5, 1.0, 0], look_at: [1.5, 0, 0], up: [0, 0, 1], view_height: 1.2, resolution: [96, 96]}
lights: [{type: directional, direction: [1, -1, 0], irradiance: 2}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: quad, size: [0.6, 0.6]}
    material: {type: mirror, reflectance: 0.9}
    transform: {translate: [1.5, 1.5, 0], rotate: [0, 0, 112.5]}
)";
constexpr double kBeamIrradiance = 1.8;
constexpr double kBeamHalfX = 0.3 * 0.38268343, kBeamHalfZ = 0.3;

}  // namespace causticbench::testing
