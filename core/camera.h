// Pinhole (perspective) and orthographic cameras; one primary ray through each pixel centre.
#pragma once

#include <optional>
#include <string>

#include <glm/vec2.hpp>

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

// What keeps a camera from making rays at one frame: the key to blame, what it should be, what it is.
struct CameraDefect {
  std::string key;
  std::string expected;
  std::string found;
};

// Nothing when the camera can make finite primary rays at `frame`: its position off look_at, its up
// vector non-zero and not parallel to the view direction, and the single-precision basis that
// CameraFrame builds finite and orthonormal.
std::optional<CameraDefect> camera_defect(const Camera& camera, double frame);

// Checks the camera at every frame in [0, frames) (only frame 0 when nothing moves it), so that no
// frame reaches the tracer with a degenerate view. `node` is the camera map being read (a scene's
// camera or an experiment's camera override); an InputError names the first defective frame.
void check_camera_at_every_frame(const Camera& camera, int frames, const ConfigNode& node);

// The camera posed for one frame, ready to make rays.
class CameraFrame {
 public:
  CameraFrame(const Camera& camera, double frame);
  // The ray through point (x + offset_x, y + offset_y) of pixel (x, y); the pixel centre by default.
  Ray primary_ray(int x, int y, float offset_x = 0.5f, float offset_y = 0.5f) const;
  // Side length in scene units of a pixel's footprint at the given distance along the view axis.
  float pixel_footprint(float distance) const;

  // Where a surface point lands on the image, for estimators that credit light to the pixel whose
  // footprint holds it (the reference's `estimator: footprint`).
  struct ImagePoint {
    int x = 0, y = 0;            // the pixel (x right, y down, as primary_ray)
    double pixels_per_area = 0;  // image area in pixels per unit of surface area there (the Jacobian du/dA)
    Vec3 to_camera{0.0f};        // unit direction from the point towards the camera (the eye, or back along
                                 // the view axis for an orthographic camera)
    float distance = 0.0f;       // to the eye (perspective) or to the image plane (orthographic)
  };
  // The pixel that sees `point` (ignoring occlusion) on a surface of unit normal `normal`, or nothing
  // when the point lies behind the camera or outside the image. For a perspective camera, with q the
  // point relative to the eye and z its depth along the view axis, du/dA = |n . q| / z^3 on the image
  // plane at depth 1 (solid angle |n . q| / |q|^3 per area, image area 1 / cos^3 per solid angle);
  // for an orthographic one |n . forward|. Divided by a pixel's area on that plane.
  std::optional<ImagePoint> project(const Vec3& point, const Vec3& normal) const;
  // Where `point` lands on the image plane in continuous pixel units (pixel (x, y) spans [x, x + 1) x
  // [y, y + 1), x right, y down), inside the image or not; nothing behind a perspective camera (at or
  // behind its eye's plane). What a method that covers an object's screen footprint projects.
  std::optional<glm::dvec2> image_position(const Vec3& point) const;
  int width() const { return width_; }
  int height() const { return height_; }
  Vec3 position() const { return origin_; }

 private:
  glm::dvec2 image_of(double sx, double sy) const;

  Camera::Type type_;
  Vec3 origin_, forward_, right_, up_;
  float half_height_;  // tan(fov/2) for perspective, view_height/2 for orthographic
  int width_, height_;
};

// Reads a scene's camera map. Its poses are checked by check_camera_at_every_frame, once the scene's
// frame count is known.
Camera read_camera(const ConfigNode& node);

}  // namespace causticbench
