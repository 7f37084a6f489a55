// lpi's per-pixel work (Wyman 2003, Section 5.1, step 2, and Section 5.2): map the receiver point
// into the object's build space, read the light samples the frame chose through the layout's
// interpolation, correct for the receiver's orientation, scale by the light. A template over the
// layout so that its stencil inlines.
#pragma once

#include <algorithm>
#include <type_traits>
#include <vector>

#include "core/gbuffer.h"
#include "core/image.h"
#include "methods/lpi/grid_lanes.h"
#include "methods/common/grid_layout.h"
#include "methods/lpi/light_samples.h"
#include "methods/lpi/multires_layout.h"
#include "methods/lpi/precompute.h"
#include "methods/lpi/shell_layout.h"

namespace causticbench::lpi {

// One light as one object sees it this frame: its reads of the object's light samples and its
// irradiance colour (a point light's at the object's centre).
struct LightView {
  LightReads reads;
  Color irradiance{0.0f};
  // storage: sh: the basis at the light's direction, one weight per coefficient block (reads unused).
  std::vector<float> harmonics;
};

enum class Outside { clamp, fade, zero };

// One object this frame: its map into build space and its lights' reads.
struct ObjectFrame {
  BuildSpaceMap map;
  std::vector<LightView> lights;
};

struct ObjectView {
  const StoredValues& values;
  const BuildSpaceMap& map;
  const LightView* lights;
  size_t light_count;
  Outside outside;
};

// The receiver's share of values read at one point: the paper orientation's cosine, or the vector
// irradiance dotted with the normal.
inline void add_shading(const float* values, const Vec3& normal, bool vector, float paper_cosine, float* sums) {
  if (!vector) {
    for (int c = 0; c < 3; ++c) sums[c] += values[c] * paper_cosine;
  } else {
    for (int c = 0; c < 3; ++c) sums[c] += normal.x * values[3 * c] + normal.y * values[3 * c + 1] + normal.z * values[3 * c + 2];
  }
}

// A light's reads with what the inner loop needs hoisted out of the pixel loop: each read's block
// and weight. Unrotated reads (nearest, barycentric, and aligned's corner at the light itself) are
// of one point, so they share one stencil per receiver point.
struct PreparedReads {
  int count = 0;
  uint32_t samples[3];  // which light sample each read is (a multires tree per light sample: its tree)
  SampleBlock blocks[3];
  float weights[3];
  bool rotated[3];
  glm::mat3 rotations[3];
  int unrotated = 0;  // how many reads are not rotated
};

inline PreparedReads prepare_reads(const StoredValues& values, const LightReads& reads) {
  PreparedReads prepared;
  prepared.count = reads.count;
  for (int r = 0; r < reads.count; ++r) {
    prepared.samples[r] = reads.reads[r].sample;
    prepared.blocks[r] = values.block(reads.reads[r].sample);
    prepared.weights[r] = reads.reads[r].weight;
    prepared.rotated[r] = reads.reads[r].rotated;
    prepared.rotations[r] = reads.reads[r].rotation;
    if (!reads.reads[r].rotated) ++prepared.unrotated;
  }
  return prepared;
}

// out[r][c] = the sum over the stencil's points of (point weight x read weight) x value, point after
// point, as StoredValues::add would add them into zeros; `Reads` reads at once, one block and read
// weight each, over the same stencil. The sums stay in local variables (the channel loop unrolled)
// rather than going through memory at every point.
template <class Decoding, int Reads>
inline void read_stencil(const Stencil& stencil, const SampleBlock* blocks, const float* read_weights, int channels,
                         float (*out)[9]) {
  constexpr int N = Decoding::channel_count;
  if constexpr (N == 0) {
    for (int r = 0; r < Reads; ++r) std::fill(out[r], out[r] + channels, 0.0f);
    for (int s = 0; s < stencil.count; ++s)
      for (int r = 0; r < Reads; ++r)
        Decoding::add(blocks[r], stencil.points[s], stencil.weights[s] * read_weights[r], channels, out[r]);
  } else {
    float sums[Reads][N] = {};
    for (int s = 0; s < stencil.count; ++s) {
#pragma GCC unroll 3
      for (int r = 0; r < Reads; ++r) {
        const uint8_t* values = Decoding::at(blocks[r], stencil.points[s], N);
        const float factor = Decoding::factor(blocks[r], stencil.weights[s] * read_weights[r]);
#pragma GCC unroll 9
        for (int c = 0; c < N; ++c) sums[r][c] += factor * Decoding::value(values, c);
      }
    }
    for (int r = 0; r < Reads; ++r)
      for (int c = 0; c < N; ++c) out[r][c] = sums[r][c];
  }
}

// Adds one object's caustic to `result` for pixels [begin, end), with the stored values' decoding
// fixed at compile time (`Decoding`, a StoredDecoding).
//
// Bit for bit the arithmetic of reading each light sample through its own stencil and
// StoredValues::add, corner after corner, then shading the reads in order (test_lpi_fast_paths.cpp
// checks it): each read keeps its own sums, added in the same order, so sharing the stencil among
// the unrotated reads and interleaving their corners changes no rounding. `PerSampleTrees` (a multires
// tree per light sample): the reads share the finest grid's stencil, each mapped through its own
// sample's tree.
template <class Layout, class Decoding, bool PerSampleTrees = false>
void add_object_caustic_decoded(const Layout& layout, const ObjectView& view, const GBuffer& gbuffer, size_t begin,
                                size_t end, Image& result) {
  const Vec3 center = layout.center();
  const float radius = layout.radius();
  const int channels = view.values.channels();
  const bool vector = channels == 9;
  std::vector<PreparedReads> prepared(view.light_count);
  for (size_t l = 0; l < view.light_count; ++l) prepared[l] = prepare_reads(view.values, view.lights[l].reads);
  for (size_t pixel = begin; pixel < end; ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    const Vec3 point = view.map.point(gbuffer.position[pixel]);
    const Vec3 normal = glm::normalize(view.map.normals * gbuffer.normal[pixel]);
    Vec3 offset = point - center;
    const float distance = glm::length(offset);
    float fade = 1.0f;
    if (distance > radius) {
      if (view.outside == Outside::zero) continue;
      if (view.outside == Outside::fade) fade = (radius / distance) * (radius / distance);
      offset *= radius / distance;  // the value on the ball's surface
    }
    // The paper's orientation: the stored irradiance is for a surface facing the centre.
    const float paper_cosine = distance > 0.0f ? std::max(0.0f, -glm::dot(normal, point - center) / distance) : 0.0f;
    // The stencil at the point itself, made once for every light's unrotated reads.
    Stencil unrotated;
    bool have_unrotated = false;
    Color total(0.0f);
    for (size_t l = 0; l < view.light_count; ++l) {
      const LightView& light = view.lights[l];
      const PreparedReads& reads = prepared[l];
      float sums[3] = {0.0f, 0.0f, 0.0f};
      if (!light.harmonics.empty()) {
        // One stencil; each of its points sums its coefficients times the basis.
        const Stencil stencil = layout.stencil(center + offset);
        float values[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        for (int s = 0; s < stencil.count; ++s) {
          for (size_t k = 0; k < light.harmonics.size(); ++k) {
            view.values.add(k, stencil.points[s], stencil.weights[s] * light.harmonics[k], values);
          }
        }
        add_shading(values, normal, vector, paper_cosine, sums);
      }
      float values[3][9];  // each read's, written whole by read_stencil (not zeroed here: a memset per point)
      if constexpr (PerSampleTrees) {
        for (int r = 0; r < reads.count; ++r) {
          if (!reads.rotated[r] && !have_unrotated) {
            unrotated = layout.finest_stencil(center + offset);
            have_unrotated = true;
          }
          Stencil stencil = reads.rotated[r] ? layout.finest_stencil(center + reads.rotations[r] * offset) : unrotated;
          layout.to_leaves(stencil, reads.samples[r]);
          read_stencil<Decoding, 1>(stencil, &reads.blocks[r], &reads.weights[r], channels, &values[r]);
        }
      } else if (reads.unrotated > 0) {
        if (!have_unrotated) {
          unrotated = layout.stencil(center + offset);
          have_unrotated = true;
        }
        if (reads.unrotated == 3) {
          // The barycentric blend: three reads, corner after corner.
          read_stencil<Decoding, 3>(unrotated, reads.blocks, reads.weights, channels, values);
        } else {
          for (int r = 0; r < reads.count; ++r) {
            if (!reads.rotated[r])
              read_stencil<Decoding, 1>(unrotated, &reads.blocks[r], &reads.weights[r], channels, &values[r]);
          }
        }
      }
      for (int r = 0; r < reads.count && !PerSampleTrees; ++r) {
        if (!reads.rotated[r]) continue;
        const Stencil stencil = layout.stencil(center + reads.rotations[r] * offset);
        read_stencil<Decoding, 1>(stencil, &reads.blocks[r], &reads.weights[r], channels, &values[r]);
      }
      for (int r = 0; r < reads.count; ++r) {
        // Vector irradiance read at R p is R E(p): dot it with R n.
        add_shading(values[r], reads.rotated[r] ? reads.rotations[r] * normal : normal, vector, paper_cosine, sums);
      }
      for (int c = 0; c < 3; ++c) total[c] += std::max(0.0f, sums[c]) * light.irradiance[c] * fade;
    }
    const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
    result.set_rgb(pixel, before + total);
  }
}

// Adds one object's caustic to `result` for pixels [begin, end), one receiver point at a time: the
// decoding of its stored values chosen once per block of pixels, not per value. What processors
// without AVX2 run, and the lanes' second implementation in test_lpi_fast_paths.cpp.
template <class Layout>
void add_object_caustic_scalar(const Layout& layout, const ObjectView& view, const GBuffer& gbuffer, size_t begin,
                               size_t end, Image& result) {
  if constexpr (std::is_same_v<Layout, MultiresLayout>) {
    if (layout.per_sample()) {
      with_decoding(view.values, [&](auto decoding) {
        add_object_caustic_decoded<Layout, decltype(decoding), true>(layout, view, gbuffer, begin, end, result);
      });
      return;
    }
  }
  with_decoding(view.values, [&](auto decoding) {
    add_object_caustic_decoded<Layout, decltype(decoding)>(layout, view, gbuffer, begin, end, result);
  });
}

// Adds one object's caustic to `result` for pixels [begin, end): on a grid, eight receiver points at
// a time in AVX2 lanes where grid_lanes_apply() allows (the same bits), else the scalar lookup.
template <class Layout>
void add_object_caustic(const Layout& layout, const ObjectView& view, const GBuffer& gbuffer, size_t begin, size_t end,
                        Image& result) {
  if constexpr (std::is_same_v<Layout, GridLayout>) {
    if (grid_lanes_apply(layout, view)) return add_grid_caustic_lanes(layout, view, gbuffer, begin, end, result);
  }
  add_object_caustic_scalar(layout, view, gbuffer, begin, end, result);
}

}  // namespace causticbench::lpi
