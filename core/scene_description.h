// JSON descriptions of a scene's content, for the keys of cached builds (store/build_cache.h): a
// precomputation is reused exactly when the description of what determines it is unchanged. Each
// description is canonical (nlohmann::json sorts keys; a track that never changes is written as its
// one value) and holds what can change a photon path, and little else: a kind's unused parameters,
// the camera and the resolution are left out, so changing them keeps the key.
#pragma once

#include <nlohmann/json.hpp>

#include "core/scene.h"

namespace causticbench {

// Kind and the parameters that kind reads; meshes add their vertex and triangle counts and hashes of
// their object-space positions, normals and triangles, so another file under the same name differs.
nlohmann::json shape_json(const ShapeDesc& shape);
// Kind and the fields that kind uses.
nlohmann::json material_json(const Material& material);
// The translate, rotate and scale tracks, every keyframe of an animated one.
nlohmann::json transform_json(const AnimatedTransform& transform);
// Kind and the fields that kind uses; environment maps add a hash of their (scaled) pixels.
nlohmann::json light_json(const Light& light);
// {name, shape, material, transform} of scene.objects[index].
nlohmann::json object_json(const Scene& scene, int index);
// Every object and light, and the frame count; never the camera.
nlohmann::json scene_content_json(const Scene& scene);

// True when nothing that photons meet changes with the frame: no animated light, no animated object
// transform, no shape that changes with the frame (moving water). The camera may still move.
bool scene_is_static(const Scene& scene);

}  // namespace causticbench
