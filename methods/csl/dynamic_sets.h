// Dynamic light for one object (Liu et al. 2008, Section 4): static CSL sets for the vertices of a
// subdivided icosahedron of light directions (methods/common/geodesic.h, the same geodesic spheres lpi
// samples light on), the spot lights of every two neighbouring directions matched by tracking
// (methods/csl/tracking.h), and per facet the triples of Section 4.3 (methods/csl/triples.h); per frame
// the facet the light's direction falls in and its barycentric weights pick the triples to interpolate
// (methods/csl/interpolation.h).
//
// Model only what the scene requires: with `all` false only the facets the rendered frames' light
// directions fall in are built (with their corners' sets and their edges' matches), not 320.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include <nlohmann/json.hpp>

#include "methods/csl/triples.h"
#include "methods/common/geodesic.h"

namespace causticbench::csl {

struct DynamicSets {
  struct Edge {
    uint32_t first = 0, second = 0;  // set indices, first's vertex below second's
    std::vector<std::array<int32_t, 2>> pairs;  // indices into the two sets (originals, then black ones)
    int matched = 0, black_first = 0, black_second = 0, tracked_lost = 0;
    double mean_distance = 0.0, seconds = 0.0;
  };
  struct Facet {
    uint32_t triangle = 0;
    std::array<uint32_t, 3> sets{};  // set index of each corner, in the mesh's corner order
    std::vector<Triple> triples;
  };

  int level = 0;
  std::vector<uint32_t> vertices;                // the geodesic vertex of each set
  std::vector<SpotLightSet> sets;                // each direction's own spot lights
  std::vector<std::vector<SpotLight>> black;     // per set, the black spot lights matching added
  std::vector<Edge> edges;
  std::vector<Facet> facets;                     // ascending triangle

  // Index -1 is no spot light; below the set's own count, its own; then its black ones.
  const SpotLight* light(uint32_t set, int32_t index) const;
  const Facet* facet(uint32_t triangle) const;
  int set_of_vertex(uint32_t vertex) const;  // -1 when that vertex has no set
  double seconds_tracking() const;
  size_t memory_bytes() const;
  nlohmann::json summary() const;  // for the run record: counts and the paper's Table 2 figures
};

struct DynamicPlan {
  int level = 2;
  bool all = false;                // every facet, or only those `directions` need
  std::vector<Vec3> directions;    // build space, towards the light
};

// `make_set(direction)`: the static set of one direction (methods/csl/generate.h through the object's
// tracer). Sets and edges are built in parallel; the result does not depend on the thread count.
DynamicSets build_dynamic_sets(const Tracer& tracer, const BoundingSphere& bounds, const SphericalMesh& mesh,
                               const DynamicPlan& plan, const std::function<SpotLightSet(const Vec3&)>& make_set,
                               const TrackingSettings& tracking);

// The facets a plan needs: those its directions fall in, and where a direction lies on an edge
// (weight below 1e-6) the facet across it too, since a lookup may land in either.
std::vector<uint32_t> planned_facets(const SphericalMesh& mesh, const DynamicPlan& plan);

}  // namespace causticbench::csl
