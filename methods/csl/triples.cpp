#include "methods/csl/triples.h"

#include <map>
#include <set>

namespace causticbench::csl {

std::vector<Triple> build_triples(const std::array<int32_t, 3>& originals, const std::array<CornerPairs, 3>& edges) {
  // partner[i][j]: the spot light at corner j paired with each one at corner i.
  std::map<int32_t, int32_t> partner[3][3];
  for (const CornerPairs& edge : edges) {
    for (const auto& pair : edge.pairs) {
      partner[edge.i][edge.j][pair[0]] = pair[1];
      partner[edge.j][edge.i][pair[1]] = pair[0];
    }
  }
  auto partner_of = [&](int from, int to, int32_t light) -> int32_t {
    const auto found = partner[from][to].find(light);
    return found == partner[from][to].end() ? -1 : found->second;
  };
  std::set<int32_t> used[3];
  auto is_used = [&](int corner, int32_t light) { return used[corner].count(light) > 0; };
  std::vector<Triple> triples;
  // Adds the triple, each corner adding where `adds` says and its light is one of its set's own.
  auto emit = [&](std::array<int32_t, 3> light, std::array<bool, 3> adds) {
    Triple triple;
    for (int c = 0; c < 3; ++c) {
      triple.light[c] = light[c];
      triple.adds[c] = adds[c] && light[c] >= 0 && light[c] < originals[c];
      if (adds[c] && light[c] >= 0) used[c].insert(light[c]);
    }
    triples.push_back(triple);
  };

  // Pass 1: triangles of matches.
  for (const CornerPairs& edge : edges) {
    const int k = 3 - edge.i - edge.j;
    for (const auto& pair : edge.pairs) {
      const int32_t x = pair[0], y = pair[1];
      const int32_t z = partner_of(edge.i, k, x);
      if (z < 0 || partner_of(edge.j, k, y) != z) continue;
      if (is_used(edge.i, x) || is_used(edge.j, y) || is_used(k, z)) continue;
      std::array<int32_t, 3> light{};
      light[edge.i] = x, light[edge.j] = y, light[k] = z;
      emit(light, {true, true, true});
    }
  }
  // Pass 2: the paper's propagation from the remaining pairs.
  for (const CornerPairs& edge : edges) {
    const int k = 3 - edge.i - edge.j;
    for (const auto& pair : edge.pairs) {
      const int32_t x = pair[0], y = pair[1];
      if (is_used(edge.i, x) || is_used(edge.j, y)) continue;
      const int32_t candidates[2] = {partner_of(edge.i, k, x), partner_of(edge.j, k, y)};
      int32_t z = -1;
      bool z_adds = false;
      for (int32_t candidate : candidates) {
        if (candidate >= 0 && !is_used(k, candidate)) {
          z = candidate;
          z_adds = true;
          break;
        }
      }
      if (z < 0) z = candidates[0] >= 0 ? candidates[0] : candidates[1];
      std::array<int32_t, 3> light{};
      std::array<bool, 3> adds{};
      light[edge.i] = x, light[edge.j] = y, light[k] = z;
      adds[edge.i] = adds[edge.j] = true;
      adds[k] = z_adds;
      emit(light, adds);
    }
  }
  // Pass 3: every corner's own spot lights in some triple.
  for (int corner = 0; corner < 3; ++corner) {
    const int j = (corner + 1) % 3, k = (corner + 2) % 3;
    for (int32_t x = 0; x < originals[corner]; ++x) {
      if (is_used(corner, x)) continue;
      std::array<int32_t, 3> light{};
      std::array<bool, 3> adds{};
      light[corner] = x, light[j] = partner_of(corner, j, x), light[k] = partner_of(corner, k, x);
      adds[corner] = true;
      emit(light, adds);
    }
  }
  return triples;
}

}  // namespace causticbench::csl
