// The method's own resampling filter for the filtered light lookups (Wand & Strasser 2003, Section
// 3.3): a mip-mapped cube map of the light and a footprint filter from the two gradient vectors of a
// differential point sample. It is written here, not taken from a library or a GPU sampler, because it
// is the subject of the research: OpenImageIO's filter costs about 0.5 us a lookup (filtered pinhole
// was 350x the unfiltered time) and a GPU's anisotropic filter is implementation-defined (lavapipe's
// ignores the gradients), so neither lets the method be measured or the backends compared. The
// definition (levels, footprint, probe rule, weights, skip) is in methods/pinhole/README.md; the Vulkan
// shader (pinhole.comp, OWN_FILTER) repeats this arithmetic on the same texels.
#pragma once

#include <cstddef>
#include <vector>

#include "core/math.h"

namespace causticbench {

// Where a footprint is probed: `count` trilinear probes at `level`, at d + offset_first + i offset_step,
// each weighted 1 / count.
struct Footprint {
  float level = 0.0f;
  int count = 1;
  Vec3 offset_first{0.0f}, offset_step{0.0f};
};

class CubeFilter {
 public:
  // Footprint assembly takes at most this many probes; a longer footprint is probed at a coarser level.
  static constexpr int kMaxAnisotropy = 16;
  // The skip's lit cones are made at most this many; a map lit in more places (an environment image)
  // is taken as lit everywhere.
  static constexpr size_t kMaxLitCones = 48;

  CubeFilter() = default;
  // `rgb`: LightCubeMap::texels() (RGB, face-major, OpenGL face layout) of `resolution`^2 x 6 texels.
  CubeFilter(const std::vector<float>& rgb, int resolution);

  // Footprint of the parallelogram centred at `direction` (unit) with edges `gradient_u` and
  // `gradient_v` (texldd's and textureGrad's convention: the edges span the whole footprint).
  Footprint footprint(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, bool anisotropic) const;
  // The filtered radiance: the weighted probes. With `skip`, a footprint whose reach meets no lit cone
  // is answered 0 without probing (exactly what the probes would sum to).
  Color lookup(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, bool anisotropic,
               bool skip = true) const;
  Color probes(const Vec3& direction, const Footprint& footprint) const;
  // Whether a texel that the footprint's probes read may be non-zero: false only when a cone around
  // `direction` that holds every such texel misses every lit cone (conservative; cheaper than
  // footprint(): no level, no probe count).
  bool may_reach_light(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, bool anisotropic) const;
  Color trilinear(const Vec3& direction, float level) const;
  // Bilinear at one level, across face borders (each face level has a border of one texel copied from
  // the neighbouring faces).
  Color bilinear(int level, const Vec3& direction) const;

  int levels() const { return static_cast<int>(sizes_.size()); }
  int level_size(int level) const { return sizes_[level]; }
  size_t level_offset(int level) const { return offsets_[level]; }  // in floats into texels()
  const std::vector<float>& texels() const { return texels_; }     // every level, padded, RGB
  bool lit_everywhere() const { return lit_everywhere_; }
  size_t lit_cone_count() const { return lit_cones_.size(); }
  size_t memory_bytes() const { return texels_.size() * sizeof(float); }
  // The skip's data for the vector pre-skip of the CPU kernel (pinhole.cpp): per lit cone its axis and
  // radius (4 floats), and support_scale() / n_0, the reach per level-0 texel of footprint width.
  std::vector<float> lit_cone_data() const;
  float support_per_texel() const { return support_scale_ / static_cast<float>(sizes_[0]); }

 private:
  std::vector<int> sizes_;
  std::vector<size_t> offsets_;
  std::vector<float> texels_;
  struct Cone {
    Vec3 axis;
    float radius;
  };
  std::vector<Cone> lit_cones_;
  bool lit_everywhere_ = false;
  float support_scale_ = 20.0f;  // the skip's bound on 10 / n_c per level-0 texel: 20 / n_0, 40 / n_0 for odd sizes

  // The two gradients' lengths in level-0 texels on the face of `direction`.
  void texel_lengths(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, float& length_u,
                     float& length_v) const;
};

// The face axes of the cube map (LightCubeMap's OpenGL layout): for a direction d on face f, the face
// coordinates are dot(s, d) / dot(major, d) and dot(t, d) / dot(major, d), in [-1, 1].
struct CubeFaceAxes {
  Vec3 s, t, major;
};
const CubeFaceAxes& cube_face_axes(int face);
int cube_face_of(const Vec3& direction);

}  // namespace causticbench
