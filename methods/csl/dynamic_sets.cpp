#include "methods/csl/dynamic_sets.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>

#include <fmt/format.h>

#include "core/parallel.h"
#include "core/progress.h"

namespace causticbench::csl {

const SpotLight* DynamicSets::light(uint32_t set, int32_t index) const {
  if (index < 0) return nullptr;
  const std::vector<SpotLight>& own = sets[set].lights;
  if (static_cast<size_t>(index) < own.size()) return &own[index];
  return &black[set][index - own.size()];
}

const DynamicSets::Facet* DynamicSets::facet(uint32_t triangle) const {
  const auto found = std::lower_bound(facets.begin(), facets.end(), triangle,
                                      [](const Facet& facet, uint32_t value) { return facet.triangle < value; });
  return found != facets.end() && found->triangle == triangle ? &*found : nullptr;
}

int DynamicSets::set_of_vertex(uint32_t vertex) const {
  const auto found = std::lower_bound(vertices.begin(), vertices.end(), vertex);
  return found != vertices.end() && *found == vertex ? static_cast<int>(found - vertices.begin()) : -1;
}

double DynamicSets::seconds_tracking() const {
  double seconds = 0.0;
  for (const Edge& edge : edges) seconds += edge.seconds;
  return seconds;
}

size_t DynamicSets::memory_bytes() const {
  size_t bytes = 0;
  for (const SpotLightSet& set : sets) bytes += set.memory_bytes();
  for (const auto& list : black) {
    for (const SpotLight& light : list) bytes += sizeof(SpotLight) + light.image.memory_bytes();
  }
  for (const Edge& edge : edges) bytes += sizeof(Edge) + edge.pairs.size() * sizeof(edge.pairs[0]);
  for (const Facet& facet : facets) bytes += sizeof(Facet) + facet.triples.size() * sizeof(Triple);
  return bytes;
}

nlohmann::json DynamicSets::summary() const {
  double lights = 0.0, triples = 0.0, blacks = 0.0, matched = 0.0, pairs = 0.0, lost = 0.0, labelled = 0.0;
  for (const SpotLightSet& set : sets) lights += static_cast<double>(set.lights.size());
  for (const auto& list : black) blacks += static_cast<double>(list.size());
  for (const Edge& edge : edges) {
    matched += edge.matched;
    pairs += static_cast<double>(edge.pairs.size());
    lost += edge.tracked_lost;
  }
  for (const Facet& facet : facets) {
    triples += static_cast<double>(facet.triples.size());
    for (const Triple& triple : facet.triples) {
      for (int c = 0; c < 3; ++c) {
        const int32_t own = static_cast<int32_t>(sets[facet.sets[c]].lights.size());
        labelled += triple.light[c] >= 0 && triple.light[c] < own && !triple.adds[c] ? 1.0 : 0.0;
      }
    }
  }
  const double directions = static_cast<double>(sets.size());
  return {{"light_subdivision", level},
          {"directions", sets.size()},
          {"edges", edges.size()},
          {"facets", facets.size()},
          {"spot_lights_per_direction", directions > 0 ? lights / directions : 0.0},
          {"triples_per_facet", facets.empty() ? 0.0 : triples / static_cast<double>(facets.size())},
          {"black_spot_lights", blacks},
          {"matched_pairs", matched},
          {"pairs", pairs},
          {"axes_lost_while_tracking", lost},
          {"labelled_corners", labelled},
          {"tracking_seconds", seconds_tracking()}};
}

std::vector<uint32_t> planned_facets(const SphericalMesh& mesh, const DynamicPlan& plan) {
  std::set<uint32_t> facets;
  if (plan.all) {
    for (uint32_t t = 0; t < mesh.triangles().size(); ++t) facets.insert(t);
  } else {
    for (const Vec3& direction : plan.directions) {
      const SphericalMesh::Location location = mesh.locate(direction);
      facets.insert(location.triangle);
      for (int e = 0; e < 3; ++e) {
        if (location.weights[e] < 1e-6f) facets.insert(mesh.neighbours()[location.triangle][e]);
      }
    }
  }
  return {facets.begin(), facets.end()};
}

DynamicSets build_dynamic_sets(const Tracer& tracer, const BoundingSphere& bounds, const SphericalMesh& mesh,
                               const DynamicPlan& plan, const std::function<SpotLightSet(const Vec3&)>& make_set,
                               const TrackingSettings& tracking) {
  DynamicSets result;
  result.level = plan.level;
  const std::vector<uint32_t> facets = planned_facets(mesh, plan);
  std::set<uint32_t> vertices;
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (uint32_t t : facets) {
    const auto& corners = mesh.triangles()[t];
    for (int c = 0; c < 3; ++c) {
      vertices.insert(corners[c]);
      const uint32_t a = corners[c], b = corners[(c + 1) % 3];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  result.vertices.assign(vertices.begin(), vertices.end());
  Progress progress("csl light directions and edges", static_cast<double>(vertices.size() + edges.size()));
  std::atomic<size_t> done{0};
  std::mutex progress_mutex;
  auto advance = [&](const char* what) {
    const size_t now = ++done;
    std::lock_guard<std::mutex> lock(progress_mutex);
    progress.update(static_cast<double>(now), what);
  };
  // The static set of every corner direction.
  result.sets.resize(result.vertices.size());
  parallel_blocks(result.vertices.size(), 1, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      result.sets[i] = make_set(mesh.points()[result.vertices[i]]);
      advance("sets");
    }
  });
  // Every edge's matches, then the black spot lights appended to their sets in edge order.
  const std::vector<std::pair<uint32_t, uint32_t>> edge_list(edges.begin(), edges.end());
  std::vector<EdgeMatch> matches(edge_list.size());
  parallel_blocks(edge_list.size(), 1, [&](size_t begin, size_t end, size_t) {
    for (size_t e = begin; e < end; ++e) {
      const int first = result.set_of_vertex(edge_list[e].first), second = result.set_of_vertex(edge_list[e].second);
      matches[e] = match_neighbours(tracer, bounds, result.sets[first], result.sets[second], tracking);
      advance("edges");
    }
  });
  progress.finish();
  result.black.resize(result.sets.size());
  std::map<std::pair<uint32_t, uint32_t>, size_t> edge_index;
  for (size_t e = 0; e < edge_list.size(); ++e) {
    EdgeMatch& match = matches[e];
    DynamicSets::Edge edge;
    edge.first = static_cast<uint32_t>(result.set_of_vertex(edge_list[e].first));
    edge.second = static_cast<uint32_t>(result.set_of_vertex(edge_list[e].second));
    // Black spot light k of a side becomes index (own count + where it lands in that set's list).
    const int32_t first_base = static_cast<int32_t>(result.sets[edge.first].lights.size() + result.black[edge.first].size());
    const int32_t second_base = static_cast<int32_t>(result.sets[edge.second].lights.size() + result.black[edge.second].size());
    for (const LightPair& pair : match.pairs) {
      edge.pairs.push_back({pair.first >= 0 ? pair.first : first_base + ~pair.first,
                            pair.second >= 0 ? pair.second : second_base + ~pair.second});
    }
    for (SpotLight& light : match.black_first) result.black[edge.first].push_back(std::move(light));
    for (SpotLight& light : match.black_second) result.black[edge.second].push_back(std::move(light));
    edge.matched = static_cast<int>(match.distances.size());
    edge.black_first = static_cast<int>(match.black_first.size());
    edge.black_second = static_cast<int>(match.black_second.size());
    edge.tracked_lost = match.tracked_lost;
    for (double distance : match.distances) edge.mean_distance += distance / std::max<size_t>(1, match.distances.size());
    edge.seconds = match.seconds;
    edge_index[edge_list[e]] = result.edges.size();
    result.edges.push_back(std::move(edge));
  }
  // Per facet, its three edges' pairs between its corners, then the triples.
  for (uint32_t t : facets) {
    const auto& corners = mesh.triangles()[t];
    DynamicSets::Facet facet;
    facet.triangle = t;
    std::array<int32_t, 3> originals{};
    for (int c = 0; c < 3; ++c) {
      facet.sets[c] = static_cast<uint32_t>(result.set_of_vertex(corners[c]));
      originals[c] = static_cast<int32_t>(result.sets[facet.sets[c]].lights.size());
    }
    std::array<CornerPairs, 3> pairs;
    for (int c = 0; c < 3; ++c) {
      const int next = (c + 1) % 3;
      const uint32_t a = corners[c], b = corners[next];
      const DynamicSets::Edge& edge = result.edges[edge_index.at({std::min(a, b), std::max(a, b)})];
      pairs[c].i = c;
      pairs[c].j = next;
      const bool forward = a < b;  // the edge's first set is corner c's
      for (const auto& pair : edge.pairs) pairs[c].pairs.push_back(forward ? pair : std::array<int32_t, 2>{pair[1], pair[0]});
    }
    facet.triples = build_triples(originals, pairs);
    result.facets.push_back(std::move(facet));
  }
  return result;
}

}  // namespace causticbench::csl
