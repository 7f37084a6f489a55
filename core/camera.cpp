#include "core/camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace causticbench {

namespace {

// A direction shorter than this cannot be normalised reliably; so short a view is no view.
constexpr double kMinimumLength = 1e-12;
// An up vector longer than this overflows single precision in the cross product of the basis.
constexpr double kMaximumUpLength = 1e12;
// Sine of the smallest angle allowed between up and the view direction.
constexpr double kMinimumSine = 1e-6;

struct CameraBasis {
  Vec3 origin, forward, right, up;
};

// The single-precision basis the rays are made from. CameraFrame and camera_defect share it, so that
// validation checks exactly what the tracer gets.
CameraBasis camera_basis(const Camera& camera, double frame) {
  CameraBasis basis;
  basis.origin = Vec3(camera.position.at(frame));
  basis.forward = glm::normalize(Vec3(camera.look_at.at(frame)) - basis.origin);
  basis.right = glm::normalize(glm::cross(basis.forward, Vec3(camera.up)));
  basis.up = glm::cross(basis.right, basis.forward);
  return basis;
}

bool is_finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool is_unit(const Vec3& v) {
  float length = glm::length(v);
  return std::isfinite(length) && std::abs(length - 1.0f) < 1e-3f;
}

bool basis_is_usable(const CameraBasis& basis) {
  return is_finite(glm::dvec3(basis.origin)) && is_unit(basis.forward) && is_unit(basis.right) && is_unit(basis.up);
}

// Length without overflow or underflow in the squares: scaled by the largest component first.
double robust_length(const glm::dvec3& v) {
  double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(largest > 0.0)) return largest;
  return largest * glm::length(v / largest);
}

glm::dvec3 robust_direction(const glm::dvec3& v) {
  double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return glm::normalize(v / largest);
}

std::string vector_text(const glm::dvec3& v) { return fmt::format("[{}, {}, {}]", v.x, v.y, v.z); }

// The key of `node` an error points at: the defect's own key when the map holds it, otherwise the
// first key it holds that also moves the camera (an override that set only `position`, keyframes).
std::string blamed_key(const ConfigNode& node, const CameraDefect& defect, bool animated) {
  std::vector<std::string> candidates;
  if (defect.key == "look_at") {
    candidates = animated ? std::vector<std::string>{"animation", "look_at", "position"}
                          : std::vector<std::string>{"look_at", "position"};
  } else if (defect.key == "up") {
    candidates = {"up", "animation", "look_at", "position"};
  } else {
    candidates = {"position", "look_at", "animation"};
  }
  std::vector<std::string> present = node.keys();
  for (const std::string& candidate : candidates) {
    if (std::find(present.begin(), present.end(), candidate) != present.end()) return candidate;
  }
  return defect.key;
}

}  // namespace

std::optional<CameraDefect> camera_defect(const Camera& camera, double frame) {
  // Each test is written as !(value >= limit) so that a NaN, which fails every comparison, fails it.
  double up_length = robust_length(camera.up);
  if (!(up_length >= kMinimumLength && up_length <= kMaximumUpLength)) {
    return CameraDefect{"up", "a non-zero up vector (length in [1e-12, 1e12])", vector_text(camera.up)};
  }
  glm::dvec3 position = camera.position.at(frame), look_at = camera.look_at.at(frame);
  glm::dvec3 view = look_at - position;
  std::string pose = fmt::format("position {} and look_at {}", vector_text(position), vector_text(look_at));
  if (!is_finite(view)) {
    return CameraDefect{"position", "a position and look_at whose difference is finite", pose};
  }
  if (!(robust_length(view) >= kMinimumLength)) {
    return CameraDefect{"look_at", "a look_at point at least 1e-12 from the camera position", pose};
  }
  glm::dvec3 forward = robust_direction(view);
  if (!(glm::length(glm::cross(forward, robust_direction(camera.up))) >= kMinimumSine)) {
    return CameraDefect{"up", "an up vector not parallel to the view direction",
                        fmt::format("up {}, parallel to the view direction {}", vector_text(camera.up),
                                    vector_text(forward))};
  }
  if (!basis_is_usable(camera_basis(camera, frame))) {
    return CameraDefect{"position",
                        "a position and look_at that single precision holds apart (rays are traced in float)", pose};
  }
  return std::nullopt;
}

void check_camera_at_every_frame(const Camera& camera, int frames, const ConfigNode& node) {
  bool animated = camera.position.animated() || camera.look_at.animated();
  // A still camera is the same at every frame.
  int checked_frames = animated ? frames : 1;
  for (int frame = 0; frame < checked_frames; ++frame) {
    std::optional<CameraDefect> defect = camera_defect(camera, frame);
    if (!defect) continue;
    std::string found = animated ? fmt::format("{} at frame {}", defect->found, frame) : defect->found;
    node.fail(blamed_key(node, *defect, animated), defect->expected, found);
  }
}

CameraFrame::CameraFrame(const Camera& camera, double frame)
    : type_(camera.type), width_(camera.width), height_(camera.height) {
  // Every reader checks the camera at every frame (check_camera_at_every_frame); a defect here is a
  // bug, and would otherwise reach the tracer as NaN rays.
  if (std::optional<CameraDefect> defect = camera_defect(camera, frame)) {
    throw std::logic_error(fmt::format("camera at frame {}: {} expected {}, found {}", frame, defect->key,
                                       defect->expected, defect->found));
  }
  CameraBasis basis = camera_basis(camera, frame);
  origin_ = basis.origin;
  forward_ = basis.forward;
  right_ = basis.right;
  up_ = basis.up;
  half_height_ = type_ == Camera::Type::perspective
                     ? static_cast<float>(std::tan(camera.fov_degrees * kPiDouble / 360.0))
                     : static_cast<float>(camera.view_height * 0.5);
}

Ray CameraFrame::primary_ray(int x, int y, float offset_x, float offset_y) const {
  float aspect = static_cast<float>(width_) / static_cast<float>(height_);
  float sx = ((x + offset_x) / width_ * 2.0f - 1.0f) * aspect * half_height_;
  float sy = (1.0f - (y + offset_y) / height_ * 2.0f) * half_height_;
  Ray ray;
  if (type_ == Camera::Type::perspective) {
    ray.origin = origin_;
    ray.direction = glm::normalize(forward_ + sx * right_ + sy * up_);
  } else {
    ray.origin = origin_ + sx * right_ + sy * up_;
    ray.direction = forward_;
  }
  return ray;
}

float CameraFrame::pixel_footprint(float distance) const {
  float per_pixel = 2.0f * half_height_ / static_cast<float>(height_);
  return type_ == Camera::Type::perspective ? per_pixel * distance : per_pixel;
}

std::optional<CameraFrame::ImagePoint> CameraFrame::project(const Vec3& point, const Vec3& normal) const {
  const double per_pixel = 2.0 * static_cast<double>(half_height_) / static_cast<double>(height_);
  const glm::dvec3 q = glm::dvec3(point) - glm::dvec3(origin_);
  const double z = glm::dot(q, glm::dvec3(forward_));
  if (!(z > 0.0)) return std::nullopt;
  double sx = glm::dot(q, glm::dvec3(right_)), sy = glm::dot(q, glm::dvec3(up_));
  ImagePoint image;
  if (type_ == Camera::Type::perspective) {
    sx /= z;
    sy /= z;
    image.pixels_per_area = std::abs(glm::dot(glm::dvec3(normal), q)) / (z * z * z) / (per_pixel * per_pixel);
    image.distance = static_cast<float>(glm::length(q));
    image.to_camera = Vec3(-q / glm::length(q));
  } else {
    image.pixels_per_area = std::abs(glm::dot(glm::dvec3(normal), glm::dvec3(forward_))) / (per_pixel * per_pixel);
    image.distance = static_cast<float>(z);
    image.to_camera = -forward_;
  }
  const glm::dvec2 at = image_of(sx, sy);
  const double px = at.x, py = at.y;
  if (!(px >= 0.0 && px < width_ && py >= 0.0 && py < height_)) return std::nullopt;
  image.x = std::min(width_ - 1, static_cast<int>(px));
  image.y = std::min(height_ - 1, static_cast<int>(py));
  return image;
}

// The inverse of primary_ray's pixel centres: x + 0.5 = (sx / (aspect h) + 1) W / 2, for (sx, sy) on the
// image plane (at depth 1 for a perspective camera, in scene units for an orthographic one).
glm::dvec2 CameraFrame::image_of(double sx, double sy) const {
  const double aspect = static_cast<double>(width_) / static_cast<double>(height_);
  return glm::dvec2((sx / (aspect * half_height_) + 1.0) * 0.5 * width_, (1.0 - sy / half_height_) * 0.5 * height_);
}

std::optional<glm::dvec2> CameraFrame::image_position(const Vec3& point) const {
  const glm::dvec3 q = glm::dvec3(point) - glm::dvec3(origin_);
  const double z = glm::dot(q, glm::dvec3(forward_));
  double sx = glm::dot(q, glm::dvec3(right_)), sy = glm::dot(q, glm::dvec3(up_));
  if (type_ == Camera::Type::perspective) {
    if (!(z > 0.0)) return std::nullopt;
    sx /= z;
    sy /= z;
  }
  return image_of(sx, sy);
}

Camera read_camera(const ConfigNode& node) {
  Camera camera;
  std::string type = node.choice_or("type", "perspective", {"perspective", "orthographic"});
  camera.type = type == "perspective" ? Camera::Type::perspective : Camera::Type::orthographic;
  camera.position = read_vec3_track(node, "position", nullptr);
  camera.look_at = read_vec3_track(node, "look_at", nullptr);
  camera.up = node.vec3_or("up", glm::dvec3(0, 1, 0));
  if (camera.type == Camera::Type::perspective) {
    camera.fov_degrees = node.number_or("fov_degrees", 40.0, 0.01, 179.0);
  } else {
    camera.view_height = node.number("view_height", 1e-9, 1e9);
  }
  std::vector<double> resolution = node.numbers("resolution", 2, 1, 16384);
  camera.width = static_cast<int>(resolution[0]);
  camera.height = static_cast<int>(resolution[1]);
  if (camera.width != resolution[0] || camera.height != resolution[1]) {
    node.fail("resolution", "two whole numbers (width, height)", "fractions");
  }
  finish_animation(node);
  node.finish();
  return camera;
}

}  // namespace causticbench
