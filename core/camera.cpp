#include "core/camera.h"

namespace causticbench {

CameraFrame::CameraFrame(const Camera& camera, double frame)
    : type_(camera.type), width_(camera.width), height_(camera.height) {
  origin_ = Vec3(camera.position.at(frame));
  forward_ = glm::normalize(Vec3(camera.look_at.at(frame)) - origin_);
  right_ = glm::normalize(glm::cross(forward_, Vec3(camera.up)));
  up_ = glm::cross(right_, forward_);
  half_height_ = type_ == Camera::Type::perspective
                     ? static_cast<float>(std::tan(camera.fov_degrees * kPiDouble / 360.0))
                     : static_cast<float>(camera.view_height * 0.5);
}

Ray CameraFrame::primary_ray(int x, int y) const {
  float aspect = static_cast<float>(width_) / static_cast<float>(height_);
  float sx = ((x + 0.5f) / width_ * 2.0f - 1.0f) * aspect * half_height_;
  float sy = (1.0f - (y + 0.5f) / height_ * 2.0f) * half_height_;
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
  glm::dvec3 forward = camera.look_at.at(0) - camera.position.at(0);
  if (glm::length(forward) < 1e-12) node.fail("look_at", "a point different from the camera position", "the same point");
  if (glm::length(glm::cross(glm::normalize(forward), glm::normalize(camera.up))) < 1e-6) {
    node.fail("up", "an up vector not parallel to the view direction", "a parallel one");
  }
  finish_animation(node);
  node.finish();
  return camera;
}

}  // namespace causticbench
