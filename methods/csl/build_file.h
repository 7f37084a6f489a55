// csl's build in the build cache (store/build_cache.h): one binary file per specular object with
// its static sets, or its dynamic sets with their black spot lights, edges and triples, written and
// read back exactly (a loaded build renders bit for bit as the computed one). Little-endian, as the
// machines this runs on; a format line first, so that a file of another format or version is refused.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "methods/csl/dynamic_sets.h"

namespace causticbench::csl {

// What the build holds of one object.
struct ObjectBuild {
  std::vector<SpotLightSet> sets;           // static sets (empty for a dynamic object)
  std::optional<DynamicSets> dynamic;
};

// Throw std::runtime_error naming `path` on a failed write, or on a file that is not a build of this
// format, truncated or inconsistent.
void write_object_build(const std::string& path, const ObjectBuild& build);
ObjectBuild read_object_build(const std::string& path);

}  // namespace causticbench::csl
