#include "core/light.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "core/assets.h"

namespace causticbench {

// The brightest environment texel accepted (W/(m^2 sr), after `scale`): HDR suns reach about 1e9;
// single-precision sums of many texels stay finite below this.
constexpr double kMaximumEnvironmentRadiance = 1e20;

EnvironmentMap::EnvironmentMap(const std::string& path, double scale, double rotation_degrees)
    : rotation_radians_(rotation_degrees * kPiDouble / 180.0) {
  auto input = OIIO::ImageInput::open(path);
  if (!input) throw InputError(fmt::format("{}: cannot open environment map: {}", path, OIIO::geterror()));
  const OIIO::ImageSpec& spec = input->spec();
  width_ = spec.width;
  height_ = spec.height;
  int channels = spec.nchannels;
  std::vector<float> raw(static_cast<size_t>(width_) * height_ * channels);
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data())) {
    throw InputError(fmt::format("{}: cannot read environment map: {}", path, input->geterror()));
  }
  pixels_.resize(static_cast<size_t>(width_) * height_ * 3);
  std::vector<double> weights(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y) {
    double sin_theta = std::sin(kPiDouble * (y + 0.5) / height_);
    for (int x = 0; x < width_; ++x) {
      size_t index = static_cast<size_t>(y) * width_ + x;
      for (int c = 0; c < 3; ++c) {
        float value = raw[index * channels + std::min(c, channels - 1)];
        // A NaN or an infinity is a broken map, not something to paint black silently (it would change
        // the light's power unnoticed). Small negative texels are the ringing of filtered HDR maps
        // (Blender's forest.exr has them, -4e-6): radiance cannot be negative, so they count as 0.
        if (!std::isfinite(value)) {
          throw InputError(fmt::format("{}: texel ({}, {}) channel {} is {}: expected finite radiance", path, x, y, c,
                                       value));
        }
        value = std::max(value, 0.0f);
        // Radiance is summed and divided by sampling probabilities in single precision: a texel near
        // float's limit (3e38) overflows those sums into infinities and NaN pixels.
        const double scaled = static_cast<double>(value) * scale;
        if (!(scaled <= kMaximumEnvironmentRadiance)) {
          throw InputError(fmt::format("{}: texel ({}, {}) channel {} is {:g} (times scale {:g}): expected radiance of at "
                                       "most {:g} W/(m^2 sr), beyond which single-precision sums overflow",
                                       path, x, y, c, value, scale, kMaximumEnvironmentRadiance));
        }
        pixels_[index * 3 + c] = static_cast<float>(scaled);
      }
      weights[index] = luminance(texel(x, y)) * sin_theta;
    }
  }
  double total = 0.0;
  for (double weight : weights) total += weight;
  if (!(total > 0.0)) {
    // Sampling it would divide 0 by 0: a map that sends no light cannot light anything.
    throw InputError(fmt::format("{}: every texel is black ({} x {}): expected an environment map that sends some light",
                                 path, width_, height_));
  }
  distribution_ = Distribution1D(weights);
}

Color EnvironmentMap::texel(int x, int y) const {
  size_t index = (static_cast<size_t>(y) * width_ + x) * 3;
  return Color(pixels_[index], pixels_[index + 1], pixels_[index + 2]);
}

void EnvironmentMap::texel_of(const Vec3& w, int& x, int& y) const {
  double theta = std::acos(std::clamp(static_cast<double>(w.y), -1.0, 1.0));
  double phi = std::atan2(static_cast<double>(w.z), static_cast<double>(w.x)) - rotation_radians_;
  phi = phi - 2.0 * kPiDouble * std::floor(phi / (2.0 * kPiDouble));
  x = std::min(width_ - 1, static_cast<int>(phi / (2.0 * kPiDouble) * width_));
  y = std::min(height_ - 1, static_cast<int>(theta / kPiDouble * height_));
}

Color EnvironmentMap::radiance(const Vec3& w) const {
  int x, y;
  texel_of(w, x, y);
  return texel(x, y);
}

Vec3 EnvironmentMap::texel_direction(int x, int y, double s, double t) const {
  const double phi = 2.0 * kPiDouble * (x + s) / width_ + rotation_radians_;
  const double cos0 = std::cos(kPiDouble * y / height_), cos1 = std::cos(kPiDouble * (y + 1) / height_);
  const double cos_theta = cos0 + (cos1 - cos0) * t;
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return Vec3(static_cast<float>(sin_theta * std::cos(phi)), static_cast<float>(cos_theta),
              static_cast<float>(sin_theta * std::sin(phi)));
}

double EnvironmentMap::texel_solid_angle(int y) const {
  return (2.0 * kPiDouble / width_) * (std::cos(kPiDouble * y / height_) - std::cos(kPiDouble * (y + 1) / height_));
}

Vec3 EnvironmentMap::sample(float u1, float u2, float u3, Color& radiance_over_pdf, float& pdf) const {
  double probability;
  size_t index = distribution_.sample(u1, probability);
  int x = static_cast<int>(index % width_), y = static_cast<int>(index / width_);
  // Uniform in solid angle inside the texel: uniform in phi, uniform in cos(theta).
  double phi = 2.0 * kPiDouble * (x + static_cast<double>(u2)) / width_ + rotation_radians_;
  double cos0 = std::cos(kPiDouble * y / height_), cos1 = std::cos(kPiDouble * (y + 1) / height_);
  double cos_theta = cos0 + (cos1 - cos0) * static_cast<double>(u3);
  double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  double texel_solid_angle = (2.0 * kPiDouble / width_) * (cos0 - cos1);
  pdf = static_cast<float>(probability / texel_solid_angle);
  radiance_over_pdf = texel(x, y) / pdf;
  return Vec3(static_cast<float>(sin_theta * std::cos(phi)), static_cast<float>(cos_theta),
              static_cast<float>(sin_theta * std::sin(phi)));
}

float EnvironmentMap::pdf(const Vec3& w) const {
  int x, y;
  texel_of(w, x, y);
  double cos0 = std::cos(kPiDouble * y / height_), cos1 = std::cos(kPiDouble * (y + 1) / height_);
  double texel_solid_angle = (2.0 * kPiDouble / width_) * (cos0 - cos1);
  return static_cast<float>(distribution_.probability(static_cast<size_t>(y) * width_ + x) / texel_solid_angle);
}

Color EnvironmentMap::upward_irradiance() const {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < height_ / 2; ++y) {
    double cos0 = std::cos(kPiDouble * y / height_), cos1 = std::cos(kPiDouble * (y + 1) / height_);
    double solid_angle = (2.0 * kPiDouble / width_) * (cos0 - cos1);
    double cos_theta = 0.5 * (cos0 + cos1);
    for (int x = 0; x < width_; ++x) sum += glm::dvec3(texel(x, y)) * solid_angle * cos_theta;
  }
  return Color(sum);
}

Vec3 LightFrame::sample_direction(float u1, float u2, float u3, Color& weight) const {
  switch (kind) {
    case LightKind::directional:
      weight = light->irradiance;
      if (cos_cone >= 1.0f) return direction_to_light;
      return sample_cone(direction_to_light, cos_cone, u1, u2);
    case LightKind::gaussian_spot: {
      // theta ~ Rayleigh(sigma), phi uniform: radiance / pdf = E sin(theta) / theta (exact weight).
      float theta = spot_sigma * std::sqrt(-2.0f * std::log(std::max(1e-30f, 1.0f - u1)));
      if (theta >= kPi) theta = kPi * 0.999f;
      float phi = 2.0f * kPi * u2;
      Vec3 t, b;
      orthonormal_basis(direction_to_light, t, b);
      float sin_theta = std::sin(theta);
      weight = light->irradiance * (theta > 0.0f ? sin_theta / theta : 1.0f);
      return glm::normalize(direction_to_light * std::cos(theta) + (t * std::cos(phi) + b * std::sin(phi)) * sin_theta);
    }
    case LightKind::environment_image: {
      float pdf;
      Vec3 direction = light->environment->sample(u1, u2, u3, weight, pdf);
      return direction;
    }
    default: weight = Color(0.0f); return direction_to_light;
  }
}

Vec3 LightFrame::sample_position(float u1, float u2) const {
  if (radius <= 0.0f) return position;
  return position + radius * sample_sphere(u1, u2);
}

LightFrame pose_light(const Light& light, double frame) {
  LightFrame posed;
  posed.light = &light;
  posed.kind = light.kind;
  posed.direction_to_light = -glm::normalize(Vec3(light.direction.at(frame)));
  posed.position = Vec3(light.position.at(frame));
  posed.radius = static_cast<float>(light.radius);
  if (light.kind == LightKind::directional) {
    posed.cos_cone = static_cast<float>(1.0 - light.solid_angle / (2.0 * kPiDouble));
  } else if (light.kind == LightKind::gaussian_spot) {
    posed.spot_sigma = static_cast<float>(std::sqrt(light.solid_angle / (2.0 * kPiDouble)));
  }
  return posed;
}

std::string light_kind_name(LightKind kind) {
  switch (kind) {
    case LightKind::directional: return "directional";
    case LightKind::point: return "point";
    case LightKind::environment_image: return "environment";
    case LightKind::gaussian_spot: return "environment (gaussian_spot)";
  }
  return "unknown";
}

std::string light_direction_defect(const glm::dvec3& direction) {
  // Written so that a NaN or an overflowing length fails the test: directions are posed in single
  // precision, where a length beyond 1e12 or below 1e-12 loses the direction.
  double length = glm::length(direction);
  if (!(length >= 1e-12 && length <= 1e12)) {
    return fmt::format("a direction of length in [1e-12, 1e12], found length {}", length);
  }
  return "";
}

Light read_light(const ConfigNode& node, const std::string& scene_folder) {
  Light light;
  light.name = node.string_or("name", "");
  std::string type = node.choice("type", {"directional", "point", "environment"});
  auto read_direction = [&]() {
    light.direction = read_vec3_track(node, "direction", nullptr);
    for (const auto& key : light.direction.keys) {
      std::string defect = light_direction_defect(key.second);
      if (!defect.empty()) {
        node.fail("direction", "a non-zero, finite direction of length in [1e-12, 1e12]",
                  fmt::format("[{}, {}, {}]", key.second.x, key.second.y, key.second.z));
      }
    }
  };
  if (type == "directional") {
    light.kind = LightKind::directional;
    read_direction();
    light.irradiance = Color(node.rgb("irradiance", 0.0, 1e9));
    bool has_diameter = node.has("angular_diameter_degrees"), has_solid_angle = node.has("solid_angle_sr");
    if (has_diameter && has_solid_angle) {
      node.fail("solid_angle_sr", "either angular_diameter_degrees or solid_angle_sr, not both", "both");
    }
    if (has_diameter) {
      double diameter = node.number("angular_diameter_degrees", 0.0, 179.0);
      light.solid_angle = 2.0 * kPiDouble * (1.0 - std::cos(diameter * kPiDouble / 360.0));
    } else {
      light.solid_angle = node.number_or("solid_angle_sr", 0.0, 0.0, 2.0 * kPiDouble);
    }
  } else if (type == "point") {
    light.kind = LightKind::point;
    light.position = read_vec3_track(node, "position", nullptr);
    light.intensity = Color(node.rgb("intensity", 0.0, 1e12));
    light.radius = node.number_or("radius", 0.0, 0.0, 1e6);
  } else {
    bool has_image = node.has("image"), has_procedural = node.has("procedural");
    if (has_image == has_procedural) {
      node.fail("image", "exactly one of 'image' (an HDR map asset) or 'procedural: gaussian_spot'",
                has_image ? "both" : "neither");
    }
    if (has_image) {
      light.kind = LightKind::environment_image;
      std::string asset = node.string("image");
      light.image_path = resolve_asset(asset, AssetKind{"environment map", {".exr", ".hdr"}}, scene_folder,
                                       node.location_of("image"));
      light.scale = node.number_or("scale", 1.0, 0.0, 1e9);
      light.rotation_degrees = node.number_or("rotation_degrees", 0.0, -360.0, 360.0);
      try {
        light.environment = std::make_shared<EnvironmentMap>(light.image_path, light.scale, light.rotation_degrees);
      } catch (const InputError& error) {
        // The decoder's message names the image; the scene's line says which light asked for it.
        throw_input_error(node.location_of("image"), node.path() + ".image",
                          "a readable HDR environment map with finite texels", error.what());
      }
    } else {
      node.choice("procedural", {"gaussian_spot"});
      light.kind = LightKind::gaussian_spot;
      read_direction();
      light.irradiance = Color(node.rgb("irradiance", 0.0, 1e9));
      light.solid_angle = node.number("solid_angle_sr", 1e-12, 1.0);
    }
  }
  finish_animation(node);
  node.finish();
  return light;
}

}  // namespace causticbench
