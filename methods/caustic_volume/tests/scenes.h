// The scenes caustic_volume's tests share.
#pragma once

namespace causticbench::testing {

// The ring of Wand's Fig. 4 (configs/scenes/ring.yaml, a plain mirror) seen straight from above, 128 x
// 128 pixels, so that every pixel of the table has the same area: the volumes' light all falls on the
// table (a vertical wall keeps the light's downward travel).
inline const char* const kRingFromAbove = R"(
camera: {type: orthographic, position: [0, 5, 0.3], look_at: [0, 0, 0.3], up: [0, 0, 1], view_height: 4.4, resolution: [128, 128]}
lights: [{type: directional, direction: [0.0, -0.5, 0.8660254], irradiance: 3.0}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.75}
  - shape: {type: ring, radius: 1.0, height: 0.5}
    material: {type: mirror, reflectance: 0.9}
)";

}  // namespace causticbench::testing
