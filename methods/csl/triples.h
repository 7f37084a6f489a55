// CSL triples (Liu et al. 2008, Section 4.3): per icosahedron facet, the spot lights of its three
// corner directions grouped in threes, which Section 4.1 interpolates. The paper's rules: (1) the
// spot lights of a triple are matched with each other; (2) the interpolation is continuous across a
// facet's edges; (3) at a corner it equals that corner's own set. Its propagation from matched pairs
// is made deterministic here, in three passes over the pairs of the facet's edges (edges 01, 12, 20,
// each in its stored order):
//   1. pairs whose third spot light closes a triangle of matches (c0-c1, c1-c2, c2-c0 all matched)
//      give triples in which every corner adds its image;
//   2. a pair of two spot lights not yet in a triple takes, at the third corner, the partner of either
//      one on the other two edges, the first one not yet used, adding; where both are used, one of them
//      is taken with its image labelled not to add (the paper's labelled CSL); where neither exists
//      (black partners made for one edge have none on the others), the corner stays empty;
//   3. a spot light of a corner that is still in no triple gets one with its partners, labelled (a
//      safety net: with tracking's complete pairings, where every spot light is in one pair of each
//      edge, pass 2 already reaches every one).
// Every spot light of a corner's own set thus adds its image in exactly one triple of each facet: at a
// corner the interpolation gives that corner's set exactly (rule 3), and the total flux is the
// barycentric blend of the corners' (tested). Rule 2 holds for the geometry wherever the matches of a
// facet's three edges agree (pass 1); where they do not, the labels of pass 2 move light between spot
// lights along an edge and the seam shows, as in the paper.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "methods/csl/tracking.h"

namespace causticbench::csl {

struct Triple {
  // Per corner of the facet (in the mesh's corner order), the spot light's index in that corner's
  // set (originals first, then the black ones that matching added), or -1 where there is none.
  std::array<int32_t, 3> light{-1, -1, -1};
  std::array<uint8_t, 3> adds{0, 0, 0};
};

// One edge's pairs between the facet's corners i and j, as indices into the two corners' sets.
struct CornerPairs {
  int i = 0, j = 1;
  std::vector<std::array<int32_t, 2>> pairs;  // (index at corner i, index at corner j)
};

// `originals[c]`: how many spot lights corner c's own set has (indices below it add light).
std::vector<Triple> build_triples(const std::array<int32_t, 3>& originals, const std::array<CornerPairs, 3>& edges);

}  // namespace causticbench::csl
