// The method's own footprint filter on a mip-mapped light cube map (declared in cube_filter.h; the
// definition is in methods/pinhole/README.md, "The filter").
#include "methods/pinhole/cube_filter.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "methods/pinhole/light_map.h"

namespace causticbench {

const CubeFaceAxes& cube_face_axes(int face) {
  // LightCubeMap::direction_to_texel: sc, tc and the major axis of each face.
  static const CubeFaceAxes axes[6] = {
      {Vec3(0, 0, -1), Vec3(0, -1, 0), Vec3(1, 0, 0)},  {Vec3(0, 0, 1), Vec3(0, -1, 0), Vec3(-1, 0, 0)},
      {Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 0)},    {Vec3(1, 0, 0), Vec3(0, 0, -1), Vec3(0, -1, 0)},
      {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)},   {Vec3(-1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1)}};
  return axes[face];
}

int cube_face_of(const Vec3& d) {
  Vec3 a = glm::abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x > 0 ? 0 : 1;
  if (a.y >= a.z) return d.y > 0 ? 2 : 3;
  return d.z > 0 ? 4 : 5;
}

namespace {

// A face level of size n is stored with a border of one texel: (n + 2)^2 RGB texels, interior texel
// (x, y) at ((y + 1) (n + 2) + x + 1).
size_t padded_index(int size, int face, int x, int y) {
  const size_t side = static_cast<size_t>(size) + 2;
  return ((static_cast<size_t>(face) * side + (y + 1)) * side + (x + 1)) * 3;
}

size_t padded_floats(int size) { return 6 * (static_cast<size_t>(size) + 2) * (static_cast<size_t>(size) + 2) * 3; }

}  // namespace

CubeFilter::CubeFilter(const std::vector<float>& rgb, int resolution) {
  for (int size = resolution;; size = std::max(1, size / 2)) {
    offsets_.push_back(texels_.size());
    sizes_.push_back(size);
    texels_.resize(texels_.size() + padded_floats(size), 0.0f);
    if (size == 1) break;
  }
  for (int face = 0; face < 6; ++face) {
    for (int y = 0; y < resolution; ++y) {
      for (int x = 0; x < resolution; ++x) {
        const float* from = &rgb[((static_cast<size_t>(face) * resolution + y) * resolution + x) * 3];
        std::copy(from, from + 3, &texels_[padded_index(resolution, face, x, y)]);
      }
    }
  }
  // Each coarser level: every texel of the level above belongs to exactly one texel below (a 2 x 2 box
  // when the size is even), weighted by its solid angle so that every level holds the same integral
  // of radiance over the sphere.
  for (int level = 1; level < levels(); ++level) {
    const int above = sizes_[level - 1], size = sizes_[level];
    float* const to = &texels_[offsets_[level]];
    const float* const from = &texels_[offsets_[level - 1]];
    for (int face = 0; face < 6; ++face) {
      for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
          double sum[3] = {0, 0, 0}, weight = 0.0;
          for (int fy = y * above / size; fy < (y + 1) * above / size; ++fy) {
            for (int fx = x * above / size; fx < (x + 1) * above / size; ++fx) {
              double solid_angle = LightCubeMap::texel_solid_angle(fx, fy, above);
              const float* p = from + padded_index(above, face, fx, fy);
              for (int c = 0; c < 3; ++c) sum[c] += solid_angle * p[c];
              weight += solid_angle;
            }
          }
          float* q = to + padded_index(size, face, x, y);
          for (int c = 0; c < 3; ++c) q[c] = static_cast<float>(sum[c] / weight);
        }
      }
    }
  }
  // Borders: the texel of the neighbouring face that holds the border texel's centre direction, so that
  // a bilinear lookup at a face edge blends across the seam (at a cube corner, one of the two faces).
  for (int level = 0; level < levels(); ++level) {
    const int size = sizes_[level];
    float* const base = &texels_[offsets_[level]];
    for (int face = 0; face < 6; ++face) {
      for (int y = -1; y <= size; ++y) {
        for (int x = -1; x <= size; ++x) {
          if (x >= 0 && x < size && y >= 0 && y < size) continue;
          Vec3 direction = LightCubeMap::texel_direction(face, (x + 0.5f) / size, (y + 0.5f) / size);
          int other;
          float s, t;
          LightCubeMap::direction_to_texel(direction, size, other, s, t);
          int ox = std::clamp(static_cast<int>(s), 0, size - 1), oy = std::clamp(static_cast<int>(t), 0, size - 1);
          const float* p = base + padded_index(size, other, ox, oy);
          std::copy(p, p + 3, base + padded_index(size, face, x, y));
        }
      }
    }
  }
  // The skip's lit cones: the lit texels of level 0 grouped by cells of an 8 x 8 grid per face, each
  // group bounded by a cone around its mean direction (plus a texel's half diagonal, at most 1.5 / n).
  const int cells = std::min(resolution, 8);
  std::map<int, std::vector<Vec3>> groups;
  for (int face = 0; face < 6; ++face) {
    for (int y = 0; y < resolution; ++y) {
      for (int x = 0; x < resolution; ++x) {
        const float* p = &rgb[((static_cast<size_t>(face) * resolution + y) * resolution + x) * 3];
        if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f) continue;
        int cell = (face * cells + y * cells / resolution) * cells + x * cells / resolution;
        groups[cell].push_back(LightCubeMap::texel_direction(face, (x + 0.5f) / resolution, (y + 0.5f) / resolution));
      }
    }
  }
  lit_everywhere_ = groups.size() > kMaxLitCones;
  support_scale_ = (resolution & (resolution - 1)) == 0 ? 20.0f : 40.0f;
  if (!lit_everywhere_) {
    for (const auto& [cell, directions] : groups) {
      Vec3 sum(0.0f);
      for (const Vec3& d : directions) sum += d;
      Cone cone{glm::normalize(sum), 0.0f};
      for (const Vec3& d : directions) {
        cone.radius = std::max(cone.radius, std::acos(std::clamp(glm::dot(cone.axis, d), -1.0f, 1.0f)));
      }
      cone.radius += 1.5f / resolution + 1e-4f;
      lit_cones_.push_back(cone);
    }
  }
}

void CubeFilter::texel_lengths(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, float& length_u,
                               float& length_v) const {
  // The derivative of the face coordinates of the lookup's face (s = n/2 (sc / major + 1)), as a GPU's
  // cube-map derivatives are taken.
  const CubeFaceAxes& axes = cube_face_axes(cube_face_of(direction));
  const float major = glm::dot(axes.major, direction);
  const float u = glm::dot(axes.s, direction) / major, v = glm::dot(axes.t, direction) / major;
  const float half = 0.5f * static_cast<float>(sizes_[0]) / major;
  auto texels = [&](const Vec3& g) {
    float along_major = glm::dot(axes.major, g);
    float ds = (glm::dot(axes.s, g) - u * along_major) * half, dt = (glm::dot(axes.t, g) - v * along_major) * half;
    return std::sqrt(ds * ds + dt * dt);
  };
  length_u = texels(gradient_u);
  length_v = texels(gradient_v);
}

Footprint CubeFilter::footprint(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v,
                                bool anisotropic) const {
  float length_u, length_v;
  texel_lengths(direction, gradient_u, gradient_v, length_u, length_v);
  const float top = static_cast<float>(levels() - 1);
  Footprint result;
  if (!anisotropic) {
    // One trilinear probe at the level whose texels are as wide as the longer edge.
    result.level = std::fmin(std::log2(std::fmax(std::fmax(length_u, length_v), 1.0f)), top);
    return result;
  }
  // Footprint assembly: probes spaced along the longer edge, at the level of the shorter one, at most
  // kMaxAnisotropy of them (a longer footprint is probed at the coarser level of longer / 16).
  const bool u_longer = length_u >= length_v;
  const float longer = std::fmax(length_u, length_v), shorter = std::fmin(length_u, length_v);
  const float ratio = std::fmin(std::ceil(longer / std::fmax(shorter, 1.0f)), static_cast<float>(kMaxAnisotropy));
  result.count = ratio >= 1.0f ? static_cast<int>(ratio) : 1;  // NaN gradients: one probe
  result.level = std::fmin(std::log2(std::fmax(std::fmax(shorter, longer / result.count), 1.0f)), top);
  const Vec3& edge = u_longer ? gradient_u : gradient_v;
  const float count = static_cast<float>(result.count);
  result.offset_step = edge / count;
  result.offset_first = edge * (0.5f / count - 0.5f);
  return result;
}

std::vector<float> CubeFilter::lit_cone_data() const {
  std::vector<float> data;
  for (const Cone& cone : lit_cones_) data.insert(data.end(), {cone.axis.x, cone.axis.y, cone.axis.z, cone.radius});
  return data;
}

bool CubeFilter::may_reach_light(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v,
                                 bool anisotropic) const {
  if (lit_everywhere_) return true;
  float length_u, length_v;
  texel_lengths(direction, gradient_u, gradient_v, length_u, length_v);
  const float longer = length_u > length_v ? length_u : length_v, shorter = length_u > length_v ? length_v : length_u;
  // The level's texels are at most `width` level-0 texels wide (footprint(): the longer edge, or the
  // shorter edge or a sixteenth of the longer), so the coarser level read, c, has 10 / n_c <=
  // support_scale_ * width / n_0 (n_c = n_0 / 2^c with 2^c <= 2 width; floor halves at most once more).
  float width = anisotropic ? std::max({shorter, longer / kMaxAnisotropy, 1.0f}) : std::max(longer, 1.0f);
  // The probes lie within half the longer gradient of the centre; a vector o moves a unit direction by
  // at most |o| / (1 - |o|) radians.
  float offset = 0.0f;
  if (anisotropic) offset = 0.5f * std::sqrt(std::max(glm::dot(gradient_u, gradient_u), glm::dot(gradient_v, gradient_v)));
  float reach = (offset < 0.5f ? offset / (1.0f - offset) : 4.0f) + support_scale_ * width / static_cast<float>(sizes_[0]);
  reach = reach * 1.001f + 1e-5f;  // float rounding of the bound
  if (!(reach < 3.0f)) return true;  // more than pi: anywhere (NaN gradients too)
  // Chords are shorter than arcs: a cone pair that overlaps has |d - axis| <= reach + radius.
  for (const Cone& cone : lit_cones_) {
    Vec3 difference = direction - cone.axis;
    float limit = reach + cone.radius + 1e-4f;
    if (glm::dot(difference, difference) <= limit * limit) return true;
  }
  return false;
}

Color CubeFilter::bilinear(int level, const Vec3& direction) const {
  const int size = sizes_[level];
  int face;
  float s, t;
  LightCubeMap::direction_to_texel(direction, size, face, s, t);
  // Texel centres at (x + 0.5); the border texels (x = -1 and x = size) hold the neighbouring faces.
  const float fx = std::fmin(std::fmax(s - 0.5f, -1.0f), size - 0.5f);
  const float fy = std::fmin(std::fmax(t - 0.5f, -1.0f), size - 0.5f);
  const float x0 = std::floor(fx), y0 = std::floor(fy);
  const float wx = fx - x0, wy = fy - y0;
  const float* p = &texels_[offsets_[level] + padded_index(size, face, static_cast<int>(x0), static_cast<int>(y0))];
  const size_t row = (static_cast<size_t>(size) + 2) * 3;
  auto texel = [&](size_t offset) { return Color(p[offset], p[offset + 1], p[offset + 2]); };
  return glm::mix(glm::mix(texel(0), texel(3), wx), glm::mix(texel(row), texel(row + 3), wx), wy);
}

Color CubeFilter::trilinear(const Vec3& direction, float level) const {
  const int finer = static_cast<int>(level);
  const float fraction = level - static_cast<float>(finer);
  Color result = bilinear(finer, direction);
  if (fraction > 0.0f && finer + 1 < levels()) result = glm::mix(result, bilinear(finer + 1, direction), fraction);
  return result;
}

Color CubeFilter::probes(const Vec3& direction, const Footprint& footprint) const {
  if (footprint.count == 1) return trilinear(direction, footprint.level);
  Color sum(0.0f);
  for (int i = 0; i < footprint.count; ++i) {
    sum += trilinear(direction + footprint.offset_first + static_cast<float>(i) * footprint.offset_step, footprint.level);
  }
  return sum * (1.0f / static_cast<float>(footprint.count));
}

Color CubeFilter::lookup(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v, bool anisotropic,
                         bool skip) const {
  if (skip && !may_reach_light(direction, gradient_u, gradient_v, anisotropic)) return Color(0.0f);
  return probes(direction, footprint(direction, gradient_u, gradient_v, anisotropic));
}

}  // namespace causticbench
