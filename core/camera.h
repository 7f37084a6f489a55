// Pinhole (perspective) and orthographic cameras; one primary ray through each pixel centre.
#pragma once

#include "core/config.h"
#include "core/math.h"
#include "core/transform.h"

namespace causticbench {

struct Camera {
  enum class Type { perspective, orthographic };
  Type type = Type::perspective;
  Vec3Track position = Vec3Track::constant(glm::dvec3(0, 1, 3));
  Vec3Track look_at = Vec3Track::constant(glm::dvec3(0.0));
  glm::dvec3 up{0, 1, 0};
  double fov_degrees = 40.0;     // perspective: vertical field of view
  double view_height = 2.0;      // orthographic: height of the view in scene units
  int width = 256;
  int height = 256;
};

// The camera posed for one frame, ready to make rays.
class CameraFrame {
 public:
  CameraFrame(const Camera& camera, double frame);
  Ray primary_ray(int x, int y) const;
  // Side length in scene units of a pixel's footprint at the given distance along the view axis.
  float pixel_footprint(float distance) const;
  int width() const { return width_; }
  int height() const { return height_; }
  Vec3 position() const { return origin_; }

 private:
  Camera::Type type_;
  Vec3 origin_, forward_, right_, up_;
  float half_height_;  // tan(fov/2) for perspective, view_height/2 for orthographic
  int width_, height_;
};

Camera read_camera(const ConfigNode& node);

}  // namespace causticbench
