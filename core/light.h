// Light sources: directional (a distant disk of given angular size, e.g. the sun), point (with an
// optional radius), and environment (a lat-long HDR image, or a procedural Gaussian spot). Directions
// and positions may be animated by frame index.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/config.h"
#include "core/math.h"
#include "core/sampling.h"
#include "core/transform.h"

namespace causticbench {

// Radiance arriving from every direction, read from a lat-long (equirectangular) image with +y up.
// Direction to the light w = (sin t cos p, cos t, sin t sin p) maps to u = p / 2pi, v = t / pi, after
// rotating the map by `rotation_degrees` about +y. Importance sampled by luminance times sin t.
class EnvironmentMap {
 public:
  EnvironmentMap(const std::string& path, double scale, double rotation_degrees);
  Color radiance(const Vec3& direction_to_light) const;
  // Draws a direction to the light; returns radiance / pdf (solid-angle pdf).
  Vec3 sample(float u1, float u2, float u3, Color& radiance_over_pdf, float& pdf) const;
  float pdf(const Vec3& direction_to_light) const;
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<float>& pixels() const { return pixels_; }  // RGB, scaled
  // Irradiance on a surface facing straight up with nothing in the way (a check on the map).
  Color upward_irradiance() const;
  // The radiance of texel (x, y), over which the map is constant.
  Color texel(int x, int y) const;
  // The direction towards the light at fractions (s, t) in [0, 1] across texel (x, y): uniform in
  // azimuth and in cos(theta) within the texel, as sample() draws, so equal steps of s and t cut the
  // texel into equal solid angles.
  Vec3 texel_direction(int x, int y, double s, double t) const;
  // The solid angle of a texel of row y (the same for every texel of the row).
  double texel_solid_angle(int y) const;

 private:
  void texel_of(const Vec3& direction_to_light, int& x, int& y) const;
  std::vector<float> pixels_;
  int width_ = 0, height_ = 0;
  double rotation_radians_ = 0.0;
  Distribution1D distribution_;  // over texels
};

enum class LightKind { directional, point, environment_image, gaussian_spot };

struct Light {
  LightKind kind = LightKind::directional;
  std::string name;
  Vec3Track direction = Vec3Track::constant(glm::dvec3(0, -1, 0));  // directional, spot: the direction light travels
  Color irradiance{1.0f};       // directional, spot: W/m^2 on a surface facing the light
  double solid_angle = 0.0;     // directional: solid angle of the source disk (sr); spot: 2 pi sigma^2
  Vec3Track position = Vec3Track::constant(glm::dvec3(0, 5, 0));  // point
  Color intensity{1.0f};        // point: W/sr
  double radius = 0.0;          // point: emission points uniform on a sphere of this radius
  std::string image_path;       // environment
  double scale = 1.0;
  double rotation_degrees = 0.0;
  std::shared_ptr<const EnvironmentMap> environment;

  bool is_distant() const { return kind != LightKind::point; }
  bool animated() const { return direction.animated() || position.animated(); }
};

// A light posed for one frame.
struct LightFrame {
  const Light* light = nullptr;
  LightKind kind = LightKind::directional;
  Vec3 direction_to_light{0, 1, 0};  // distant lights: towards the light (the reverse of travel)
  float cos_cone = 1.0f;             // directional: cosine of the source's angular radius
  float spot_sigma = 0.0f;           // spot: Gaussian angular standard deviation (radians)
  Vec3 position{0.0f};
  float radius = 0.0f;

  // Distant lights: draws a direction towards the light; returns radiance / pdf, in W/m^2.
  Vec3 sample_direction(float u1, float u2, float u3, Color& weight) const;
  // Point lights: draws an emission point.
  Vec3 sample_position(float u1, float u2) const;
};

LightFrame pose_light(const Light& light, double frame);
// Why `direction` cannot be a light's direction (zero, not finite, or so long or short that its
// single-precision normalisation is not finite), or "" when it can.
std::string light_direction_defect(const glm::dvec3& direction);
Light read_light(const ConfigNode& node, const std::string& scene_folder);
std::string light_kind_name(LightKind kind);

}  // namespace causticbench
