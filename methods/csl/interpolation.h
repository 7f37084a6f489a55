// CSL interpolation (Liu et al. 2008, Section 4.1): a spot light for a light direction inside an
// icosahedron facet, made from one triple of spot lights of the facet's three corner directions with
// the direction's barycentric weights: the axes interpolated on the sphere, the light plane origins,
// the profiles and the intensity images linearly, each image first turned with the rotation that takes
// its axis onto the interpolated one.
//
// The blended image is not resampled: it keeps its (up to three) source images with their weights and
// the 2x2 maps from its plane coordinates into theirs, and blends at each lookup. That is exact
// (a resampled image would blur twice) and costs nothing per frame beyond a few vectors per triple.
#pragma once

#include <array>
#include <optional>

#include "methods/csl/spot_light.h"

namespace causticbench::csl {

// An image blended from up to three stored images, read through the Image concept of spot_light.h.
class BlendedImage {
 public:
  struct Source {
    const IntensityImage* image = nullptr;
    float weight = 0.0f;
    // (x, y) in the blended light's plane -> (map[0] x + map[1] y, map[2] x + map[3] y) in the source's.
    double map[4] = {1.0, 0.0, 0.0, 1.0};
  };
  void add(const Source& source);
  int count() const { return count_; }
  const Source& source(int i) const { return sources_[i]; }

  int channels() const { return channels_; }
  double max_radius() const { return max_radius_; }
  bool lookup(double x, double y, float* out) const;
  void flux_within(double r, double* out) const;
  // Its sources' largest, with a margin for their maps, which turn a plane (u and v are float) into
  // another only up to about 1e-7 of a radius.
  double support_radius() const { return support_radius_; }

 private:
  std::array<Source, 3> sources_{};
  int count_ = 0;
  int channels_ = 1;
  double max_radius_ = 0.0;
  double support_radius_ = 0.0;
};

struct InterpolatedSpotLight {
  SpotGeometry geometry;
  BlendedImage image;

  template <class Visible = AlwaysVisible>
  int evaluate(const Vec3& point, const Vec3& normal, float footprint_radius, const EvaluationSettings& settings,
               float* out, const Visible& visible = {}) const {
    return evaluate_spot_light(geometry, image, point, normal, footprint_radius, settings, out, visible);
  }
};

// How alpha and beta of f(r) = alpha / (1 + beta r) are interpolated: the paper's linear alpha
// (`distance`; where a corner is collimated or diverging, alpha is infinite or negative and the
// blend falls back to curvature), or linear kappa = 1 / alpha (`curvature`), which stays finite and
// continuous through the collimated case.
enum class FocusInterpolation { curvature, distance };

// One corner of a triple: its spot light (nullptr where the triple has none at this corner, see
// methods/csl/triples.h), the direction's barycentric weight of the corner, and whether the corner's
// image adds (Section 4.3's labelled CSLs do not).
struct TripleCorner {
  const SpotLight* light = nullptr;
  float weight = 0.0f;
  bool adds = true;
};

// The interpolated spot light of a triple, or nothing when no corner with a positive weight adds
// light. Corners without a light take no part in the geometry; their weight still scales the
// others' images down, so that their light fades out towards the corner that lacks them.
std::optional<InterpolatedSpotLight> interpolate_triple(const std::array<TripleCorner, 3>& corners,
                                                        FocusInterpolation focus);

// The weighted spherical mean of unit vectors (Buss & Fillmore 2001): the point q of the sphere where
// the weighted sum of the logarithm maps log_q(a_i) vanishes; the normalised weighted sum where the
// iteration cannot run (antipodal inputs). Equals a_i exactly when only a_i has weight.
glm::dvec3 spherical_mean(const std::array<glm::dvec3, 3>& directions, const std::array<double, 3>& weights);

// The 2x2 map from the plane of `to` into the plane of `from` under the rotation that takes from.axis
// to to.axis about their cross product (the paper's R), in each plane's (u, v) coordinates.
void plane_map(const SpotGeometry& to, const SpotGeometry& from, double* map);

}  // namespace causticbench::csl
