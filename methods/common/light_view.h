// A camera at a light: orthographic along a directional light's travel, perspective from a point light,
// over a square window of the light's view. What shadow mapping renders from, and what caustics mapping
// (methods/caustic_mapping/) renders its receiver map, photon buffer and caustic map from; per-frame
// photon methods use it for their emission maps over the specular objects' light-space bounds.
#pragma once

#include <optional>
#include <vector>

#include "core/light.h"
#include "core/math.h"
#include "core/scene.h"

namespace causticbench {

class LightView {
 public:
  // Orthographic: rays travel along `travel` (unit); the window is the square of side 2 * half_extent
  // around `centre` in the plane perpendicular to it.
  static LightView orthographic(const Vec3& travel, const Vec3& centre, double half_extent);
  // Perspective from `eye` towards `centre`; the window is the square of half-side tan_half at unit depth.
  static LightView perspective(const Vec3& eye, const Vec3& centre, double tan_half);

  bool is_orthographic() const { return orthographic_; }
  // Window coordinates of a point: (s, t) in [0, 1]^2 inside the window, and its depth (along the
  // travel direction for orthographic, from the eye along the axis for perspective).
  struct Projected {
    double s = 0, t = 0, depth = 0;
  };
  // Nothing for a point behind a perspective eye.
  std::optional<Projected> project(const Vec3& point) const;
  // The ray through window point (s, t): its origin (on a plane `back` behind the window's centre for
  // orthographic, the eye for perspective) and unit direction.
  Ray ray(double s, double t, double back) const;
  // The direction light travels at a point (unit): the view axis (orthographic), away from the eye.
  Vec3 travel_at(const Vec3& point) const;
  // The cross-section of one texel of an n x n grid over the window, where the light meets a point:
  // its area perpendicular to the travel direction (orthographic), or its solid angle seen from the eye
  // (perspective) for texel (x, y). A photon's flux is the light's irradiance or intensity times it.
  double texel_measure(int x, int y, int n) const;
  // Where a window of the same kind, looking the same way, holds every point of `points` (light-space
  // bounds) with `margin` of its half-size around them. Points behind a perspective eye are left out
  // (no window holds them); nothing when no point is left.
  // A perspective window reaches at most `widest_tan` off its axis (the tangent of its widest angle):
  // points beyond it are held at that edge (what falls outside is the caller's to count).
  static std::optional<LightView> fitted(const LightView& like, const std::vector<Vec3>& points, double margin,
                                         double widest_tan = 1e30);
  const Vec3& eye() const { return eye_; }
  const Vec3& axis() const { return axis_; }
  double half_extent() const { return half_extent_; }
  // The window's frame (a Vulkan backend repeats project() from them): its axes across the view, and its
  // centre off the axis in window units.
  const Vec3& right() const { return right_; }
  const Vec3& up() const { return up_; }
  double offset_s() const { return offset_s_; }
  double offset_t() const { return offset_t_; }

 private:
  bool orthographic_ = true;
  Vec3 eye_{0.0f};     // perspective: the light; orthographic: the window's centre
  Vec3 axis_{0, -1, 0};
  Vec3 right_{1, 0, 0}, up_{0, 0, 1};
  double half_extent_ = 1.0;  // orthographic: half-side in scene units; perspective: tan of the half-angle
  double offset_s_ = 0.0, offset_t_ = 0.0;  // the window's centre off the axis (fitted windows), in its units
};

// The light view of `light` that covers `bounds` (a specular object's bounding sphere), with its
// window fitted to the sphere's silhouette. A point light inside the sphere, or seeing it under more
// than max_half_angle, gets a window of that half-angle (what it misses is the caller's to count).
// Environment lights have no single view: nothing.
std::optional<LightView> light_view_of(const LightFrame& light, const BoundingSphere& bounds, double max_half_angle);

}  // namespace causticbench
