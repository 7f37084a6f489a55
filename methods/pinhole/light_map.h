// The incoming light as an environment map, rebuilt every frame from the scene's lights (Wand &
// Strasser 2003, Section 3.1): a cube map of radiance (W / m^2 / sr) for the unfiltered lookups and a
// mip-mapped lat-long texture for OpenImageIO's filtered lookups with derivatives.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/scene.h"


namespace causticbench {

// Radiance arriving from a direction, summed over the posed lights, with every light treated as
// distant from `center` (a point light becomes a directional light of irradiance I / d^2 and, with a
// radius, angular size pi r^2 / d^2). Sources smaller than the map's texels are kept with their exact
// total irradiance (see LightCubeMap).
class DistantLights {
 public:
  DistantLights(const SceneFrame& frame, const Vec3& center);

  struct Source {
    LightKind kind;
    Vec3 direction_to_light;
    float cos_cone = 1.0f;   // disk sources
    float sigma = 0.0f;      // Gaussian spot
    Color irradiance{0.0f};  // W / m^2 on a surface facing the source
    float solid_angle = 0.0f;
    const EnvironmentMap* environment = nullptr;
  };
  const std::vector<Source>& sources() const { return sources_; }
  // Equal when every source is the same (so a light map built from one serves the other).
  bool operator==(const DistantLights& other) const;
  Color radiance(const Source& source, const Vec3& direction) const;

 private:
  std::vector<Source> sources_;
};

// Cube map with the OpenGL face layout (+x, -x, +y, -y, +z, -z).
class LightCubeMap {
 public:
  LightCubeMap() = default;
  LightCubeMap(const DistantLights& lights, int resolution);
  // Bilinear within the face (clamped at face borders). Inline: it is the inner loop of the method.
  Color lookup(const Vec3& direction) const {
    int face;
    float s, t;
    direction_to_texel(direction, resolution_, face, s, t);
    return lookup_texel(face, s, t);
  }
  // The same from face coordinates in texels (as direction_to_texel gives them).
  Color lookup_texel(int face, float s, float t) const {
    float fx = std::clamp(s - 0.5f, 0.0f, resolution_ - 1.0f), fy = std::clamp(t - 0.5f, 0.0f, resolution_ - 1.0f);
    int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    // Most of a compact light's map is black: a coarse occupancy mask skips those fetches exactly.
    if (!occupied_[(static_cast<size_t>(face) * blocks_ + y0 / kOccupancyBlock) * blocks_ + x0 / kOccupancyBlock]) {
      return Color(0.0f);
    }
    int x1 = std::min(x0 + 1, resolution_ - 1), y1 = std::min(y0 + 1, resolution_ - 1);
    float wx = fx - static_cast<float>(x0), wy = fy - static_cast<float>(y0);
    const float* base = texels_.data() + static_cast<size_t>(face) * resolution_ * resolution_ * 3;
    auto texel = [&](int x, int y) {
      const float* p = base + (static_cast<size_t>(y) * resolution_ + x) * 3;
      return Color(p[0], p[1], p[2]);
    };
    return glm::mix(glm::mix(texel(x0, y0), texel(x1, y0), wx), glm::mix(texel(x0, y1), texel(x1, y1), wx), wy);
  }
  int resolution() const { return resolution_; }
  // The coarse occupancy mask: one byte per kOccupancyBlock^2 texels of a face, (face * blocks + by) *
  // blocks + bx, non-zero where a bilinear lookup whose first texel lies in that block can be non-zero.
  static constexpr int kOccupancyBlock = 8;
  int occupancy_blocks() const { return blocks_; }
  const std::vector<uint8_t>& occupancy() const { return occupied_; }
  const std::vector<float>& texels() const { return texels_; }  // RGB, face-major
  size_t memory_bytes() const { return texels_.size() * sizeof(float); }
  // Sum of radiance x texel solid angle over the map, per channel: the irradiance a sphere of
  // directions receives (checks the normalisation).
  Color integral() const;

  static void direction_to_texel(const Vec3& d, int resolution, int& face, float& s, float& t) {
    Vec3 a = glm::abs(d);
    float major, sc, tc;
    if (a.x >= a.y && a.x >= a.z) {
      face = d.x > 0 ? 0 : 1;
      major = a.x;
      sc = d.x > 0 ? -d.z : d.z;
      tc = -d.y;
    } else if (a.y >= a.z) {
      face = d.y > 0 ? 2 : 3;
      major = a.y;
      sc = d.x;
      tc = d.y > 0 ? d.z : -d.z;
    } else {
      face = d.z > 0 ? 4 : 5;
      major = a.z;
      sc = d.z > 0 ? d.x : -d.x;
      tc = -d.y;
    }
    float scale = 0.5f * static_cast<float>(resolution) / major;
    s = sc * scale + 0.5f * static_cast<float>(resolution);
    t = tc * scale + 0.5f * static_cast<float>(resolution);
  }
  static Vec3 texel_direction(int face, float s, float t);  // s, t in [0, 1]
  static float texel_solid_angle(int face_x, int face_y, int resolution);

 private:
  int resolution_ = 0;
  int blocks_ = 0;  // per face side
  std::vector<float> texels_;
  std::vector<uint8_t> occupied_;  // per block: a texel of it, or of the texel row/column after it, is non-zero
};

// A lat-long copy of the light map as an OpenImageIO mip-mapped environment texture (written to a
// temporary TIFF file, removed on destruction, or by the next process if this one is killed), for
// filtered lookups with direction derivatives.
class FilteredLightMap {
 public:
  FilteredLightMap(const DistantLights& lights, int height);
  ~FilteredLightMap();
  FilteredLightMap(const FilteredLightMap&) = delete;
  FilteredLightMap& operator=(const FilteredLightMap&) = delete;
  // anisotropic: footprint assembly along both gradients; otherwise isotropic (the larger gradient).
  Color lookup(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, bool anisotropic) const;
  size_t memory_bytes() const { return bytes_; }

 private:
  struct State;
  std::unique_ptr<State> state_;
  size_t bytes_ = 0;
};

// FilteredLightMap's texture files are named after their process; one killed mid-run leaves its file
// behind. Removes, from `folder`, the files of processes that no longer exist; returns how many.
size_t remove_stale_light_map_files(const std::filesystem::path& folder);

}  // namespace causticbench
