#include "methods/pinhole/light_map.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include <atomic>
#include <filesystem>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <Imath/ImathVec.h>
#include <OpenImageIO/texture.h>
#include <fmt/format.h>

#include "core/parallel.h"

namespace causticbench {

DistantLights::DistantLights(const SceneFrame& frame, const Vec3& center) {
  for (const LightFrame& light : frame.lights) {
    Source source;
    source.kind = light.kind;
    source.direction_to_light = light.direction_to_light;
    switch (light.kind) {
      case LightKind::directional:
        source.irradiance = light.light->irradiance;
        source.cos_cone = light.cos_cone;
        source.solid_angle = static_cast<float>(light.light->solid_angle);
        break;
      case LightKind::gaussian_spot:
        source.irradiance = light.light->irradiance;
        source.sigma = light.spot_sigma;
        source.solid_angle = static_cast<float>(light.light->solid_angle);
        break;
      case LightKind::environment_image: source.environment = light.light->environment.get(); break;
      case LightKind::point: {
        // Distant from the reflector's centre, as the paper assumes.
        Vec3 offset = light.position - center;
        float distance2 = std::max(1e-12f, glm::dot(offset, offset));
        source.kind = LightKind::directional;
        source.direction_to_light = offset / std::sqrt(distance2);
        source.irradiance = light.light->intensity / distance2;
        source.solid_angle = kPi * light.radius * light.radius / distance2;
        source.cos_cone = 1.0f - source.solid_angle / (2.0f * kPi);
        break;
      }
    }
    sources_.push_back(source);
  }
}

bool DistantLights::operator==(const DistantLights& other) const {
  if (sources_.size() != other.sources_.size()) return false;
  for (size_t i = 0; i < sources_.size(); ++i) {
    const Source &a = sources_[i], &b = other.sources_[i];
    if (a.kind != b.kind || a.direction_to_light != b.direction_to_light || a.cos_cone != b.cos_cone || a.sigma != b.sigma ||
        a.irradiance != b.irradiance || a.solid_angle != b.solid_angle || a.environment != b.environment) {
      return false;
    }
  }
  return true;
}

Color DistantLights::radiance(const Source& source, const Vec3& direction) const {
  switch (source.kind) {
    case LightKind::directional:
      if (source.solid_angle <= 0.0f) return Color(0.0f);
      return glm::dot(direction, source.direction_to_light) >= source.cos_cone ? source.irradiance / source.solid_angle
                                                                               : Color(0.0f);
    case LightKind::gaussian_spot: {
      float theta = std::acos(std::clamp(glm::dot(direction, source.direction_to_light), -1.0f, 1.0f));
      float variance = source.sigma * source.sigma;
      return source.irradiance * (std::exp(-theta * theta / (2.0f * variance)) / (2.0f * kPi * variance));
    }
    case LightKind::environment_image: return source.environment->radiance(direction);
    default: return Color(0.0f);
  }
}

Vec3 LightCubeMap::texel_direction(int face, float s, float t) {
  float sc = 2.0f * s - 1.0f, tc = 2.0f * t - 1.0f;
  Vec3 d;
  switch (face) {
    case 0: d = Vec3(1.0f, -tc, -sc); break;
    case 1: d = Vec3(-1.0f, -tc, sc); break;
    case 2: d = Vec3(sc, 1.0f, tc); break;
    case 3: d = Vec3(sc, -1.0f, -tc); break;
    case 4: d = Vec3(sc, -tc, 1.0f); break;
    default: d = Vec3(-sc, -tc, -1.0f); break;
  }
  return glm::normalize(d);
}

float LightCubeMap::texel_solid_angle(int x, int y, int resolution) {
  // Exact: the solid angle of the face rectangle [a0, a1] x [b0, b1] at distance 1 is the difference of
  // atan(a b / sqrt(a^2 + b^2 + 1)) at its corners.
  auto corner = [](double a, double b) { return std::atan2(a * b, std::sqrt(a * a + b * b + 1.0)); };
  double a0 = 2.0 * x / resolution - 1.0, a1 = 2.0 * (x + 1) / resolution - 1.0;
  double b0 = 2.0 * y / resolution - 1.0, b1 = 2.0 * (y + 1) / resolution - 1.0;
  return static_cast<float>(corner(a1, b1) - corner(a0, b1) - corner(a1, b0) + corner(a0, b0));
}

namespace {

// Rasterises every source into a map of `texel_count` texels given by (direction at sub-position,
// solid angle) callbacks, supersampled 4 x 4, and rescales each compact source so that the map holds
// exactly its irradiance (a source smaller than a texel lands in the texel that holds its direction).
template <typename DirectionOf, typename SolidAngleOf, typename TexelOf>
void rasterise(const DistantLights& lights, size_t texel_count, DirectionOf direction_of, SolidAngleOf solid_angle_of,
               TexelOf texel_of, std::vector<float>& texels) {
  texels.assign(texel_count * 3, 0.0f);
  std::vector<float> layer(texel_count * 3);
  for (const DistantLights::Source& source : lights.sources()) {
    std::fill(layer.begin(), layer.end(), 0.0f);
    parallel_blocks(texel_count, 4096, [&](size_t begin, size_t end, size_t) {
      for (size_t texel = begin; texel < end; ++texel) {
        Color sum(0.0f);
        for (int sy = 0; sy < 4; ++sy) {
          for (int sx = 0; sx < 4; ++sx) sum += lights.radiance(source, direction_of(texel, (sx + 0.5f) / 4.0f, (sy + 0.5f) / 4.0f));
        }
        sum /= 16.0f;
        layer[3 * texel] = sum.r;
        layer[3 * texel + 1] = sum.g;
        layer[3 * texel + 2] = sum.b;
      }
    });
    if (source.kind != LightKind::environment_image) {
      glm::dvec3 integral(0.0);
      for (size_t texel = 0; texel < texel_count; ++texel) {
        integral += glm::dvec3(layer[3 * texel], layer[3 * texel + 1], layer[3 * texel + 2]) * static_cast<double>(solid_angle_of(texel));
      }
      double expected = luminance(source.irradiance), found = luminance(Color(integral));
      if (found > 0.0) {
        float scale = static_cast<float>(expected / found);
        for (float& value : layer) value *= scale;
      } else if (expected > 0.0) {
        size_t texel = texel_of(source.direction_to_light);
        Color radiance = source.irradiance / solid_angle_of(texel);
        layer[3 * texel] = radiance.r;
        layer[3 * texel + 1] = radiance.g;
        layer[3 * texel + 2] = radiance.b;
      }
    }
    for (size_t i = 0; i < layer.size(); ++i) texels[i] += layer[i];
  }
}

}  // namespace

LightCubeMap::LightCubeMap(const DistantLights& lights, int resolution) : resolution_(resolution) {
  size_t face_size = static_cast<size_t>(resolution) * resolution;
  auto direction_of = [&](size_t texel, float fx, float fy) {
    int face = static_cast<int>(texel / face_size);
    size_t index = texel % face_size;
    float x = static_cast<float>(index % resolution), y = static_cast<float>(index / resolution);
    return texel_direction(face, (x + fx) / resolution, (y + fy) / resolution);
  };
  auto solid_angle_of = [&](size_t texel) {
    size_t index = texel % face_size;
    return texel_solid_angle(static_cast<int>(index % resolution), static_cast<int>(index / resolution), resolution);
  };
  auto texel_of = [&](const Vec3& direction) {
    int face;
    float s, t;
    direction_to_texel(direction, resolution, face, s, t);
    int x = std::clamp(static_cast<int>(s), 0, resolution - 1), y = std::clamp(static_cast<int>(t), 0, resolution - 1);
    return face * face_size + static_cast<size_t>(y) * resolution + x;
  };
  rasterise(lights, 6 * face_size, direction_of, solid_angle_of, texel_of, texels_);
  // A bilinear lookup whose lower-left texel is (x0, y0) reads x0..x0+1, y0..y0+1: mark the block of
  // (x0, y0) for every non-zero texel at (x, y) with x0 in {x - 1, x} and y0 in {y - 1, y}.
  blocks_ = (resolution + kOccupancyBlock - 1) / kOccupancyBlock;
  occupied_.assign(static_cast<size_t>(6) * blocks_ * blocks_, 0);
  for (int face = 0; face < 6; ++face) {
    for (int y = 0; y < resolution; ++y) {
      for (int x = 0; x < resolution; ++x) {
        const float* p = &texels_[((static_cast<size_t>(face) * resolution + y) * resolution + x) * 3];
        if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f) continue;
        for (int y0 : {y - 1, y}) {
          for (int x0 : {x - 1, x}) {
            if (x0 < 0 || y0 < 0) continue;
            occupied_[(static_cast<size_t>(face) * blocks_ + y0 / kOccupancyBlock) * blocks_ + x0 / kOccupancyBlock] = 1;
          }
        }
      }
    }
  }
}

Color LightCubeMap::integral() const {
  glm::dvec3 sum(0.0);
  size_t face_size = static_cast<size_t>(resolution_) * resolution_;
  for (size_t texel = 0; texel < 6 * face_size; ++texel) {
    size_t index = texel % face_size;
    double solid_angle = texel_solid_angle(static_cast<int>(index % resolution_), static_cast<int>(index / resolution_), resolution_);
    sum += glm::dvec3(texels_[3 * texel], texels_[3 * texel + 1], texels_[3 * texel + 2]) * solid_angle;
  }
  return Color(sum);
}

struct FilteredLightMap::State {
  std::string path;
  OIIO::TextureSystem* system = nullptr;
  OIIO::TextureSystem::TextureHandle* handle = nullptr;
};

namespace {

// OpenImageIO's lat-long layout with +y up (checked by methods/pinhole/tests/test_pinhole.cpp against the cube map):
// v = theta / pi from +y, u = phi / 2 pi with direction (sin theta sin phi, cos theta, -sin theta cos phi).
Vec3 latlong_direction(float u, float v) {
  float phi = 2.0f * kPi * u, theta = kPi * v;
  return Vec3(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
}

void latlong_coordinates(const Vec3& d, float& u, float& v) {
  v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
  u = std::atan2(d.x, -d.z) / (2.0f * kPi);
  if (u < 0.0f) u += 1.0f;
}

constexpr const char* kLightMapFilePrefix = "causticbench-lightmap-";

}  // namespace

size_t remove_stale_light_map_files(const std::filesystem::path& folder) {
  size_t removed = 0;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    std::string name = entry.path().filename().string();
    if (name.rfind(kLightMapFilePrefix, 0) != 0) continue;
    long owner = std::strtol(name.c_str() + std::strlen(kLightMapFilePrefix), nullptr, 10);
    if (owner <= 0 || owner == getpid()) continue;
    if (kill(static_cast<pid_t>(owner), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
    std::error_code ignored;
    if (std::filesystem::remove(entry.path(), ignored)) ++removed;
  }
  return removed;
}

FilteredLightMap::FilteredLightMap(const DistantLights& lights, int height) : state_(std::make_unique<State>()) {
  int width = 2 * height;
  size_t count = static_cast<size_t>(width) * height;
  std::vector<float> texels;
  auto direction_of = [&](size_t texel, float fx, float fy) {
    return latlong_direction((static_cast<float>(texel % width) + fx) / width, (static_cast<float>(texel / width) + fy) / height);
  };
  auto solid_angle_of = [&](size_t texel) {
    double y = static_cast<double>(texel / width);
    return static_cast<float>(2.0 * kPiDouble / width * (std::cos(kPiDouble * y / height) - std::cos(kPiDouble * (y + 1) / height)));
  };
  auto texel_of = [&](const Vec3& direction) {
    float u, v;
    latlong_coordinates(direction, u, v);
    size_t x = std::min<size_t>(width - 1, static_cast<size_t>(u * width));
    size_t y = std::min<size_t>(height - 1, static_cast<size_t>(v * height));
    return y * width + x;
  };
  rasterise(lights, count, direction_of, solid_angle_of, texel_of, texels);
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf buffer(spec, texels.data());
  static std::once_flag cleaned;
  std::call_once(cleaned, [] { remove_stale_light_map_files(std::filesystem::temp_directory_path()); });
  static std::atomic<int> counter{0};
  // TIFF, not OpenEXR: for OpenEXR lat-long maps OpenImageIO's maketx switches to its "shared border"
  // convention (oiio:sampleborder), in which the first and last columns are the same direction. Our
  // texels are centred at (x + 0.5) / width, so the lookup then drops one column at the u = 0 seam: a
  // compact light straddling it (the ring scene's light sits exactly on it) lost about 20 % of its
  // energy. TIFF keeps the ordinary pixel-centre convention.
  state_->path = (std::filesystem::temp_directory_path() /
                  fmt::format("{}{}-{}.tx", kLightMapFilePrefix, getpid(), counter++)).string();
  OIIO::ImageSpec config;
  config.attribute("maketx:wrapmodes", "periodic,clamp");
  if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxEnvLatl, buffer, state_->path, config)) {
    throw std::runtime_error("cannot make the light map texture: " + OIIO::geterror());
  }
  bytes_ = count * 3 * sizeof(float) * 4 / 3;
  state_->system = OIIO::TextureSystem::create(false);
  state_->system->attribute("max_memory_MB", 512.0f);
  state_->handle = state_->system->get_texture_handle(OIIO::ustring(state_->path));
}

FilteredLightMap::~FilteredLightMap() {
  if (state_->system) OIIO::TextureSystem::destroy(state_->system);
  std::error_code ignored;
  std::filesystem::remove(state_->path, ignored);
}

Color FilteredLightMap::lookup(const Vec3& direction, const Vec3& gradient_u, const Vec3& gradient_v,
                               bool anisotropic) const {
  OIIO::TextureOpt options;
  options.mipmode = anisotropic ? OIIO::TextureOpt::MipModeAniso : OIIO::TextureOpt::MipModeTrilinear;
  options.interpmode = OIIO::TextureOpt::InterpBilinear;
  options.anisotropic = 16;
  float result[3] = {0, 0, 0};
  Imath::V3f R(direction.x, direction.y, direction.z), dRdx(gradient_u.x, gradient_u.y, gradient_u.z),
      dRdy(gradient_v.x, gradient_v.y, gradient_v.z);
  if (!anisotropic) {
    // Isotropic: a round footprint as wide as the longer gradient.
    float length = std::max(glm::length(gradient_u), glm::length(gradient_v));
    Vec3 t, b;
    orthonormal_basis(direction, t, b);
    dRdx = Imath::V3f(t.x, t.y, t.z) * length;
    dRdy = Imath::V3f(b.x, b.y, b.z) * length;
  }
  state_->system->environment(state_->handle, nullptr, options, R, dRdx, dRdy, 3, result);
  return Color(result[0], result[1], result[2]);
}

}  // namespace causticbench
