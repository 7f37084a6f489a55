// A caustic spot light (Liu et al. 2008, Section 2): a light plane through origin c with normal a (the
// optical axis), from whose every point p at radius r one ray leaves towards the axis point
// c + f(r) a, f(r) = alpha / (1 + beta r) (Eq. 1), with the intensity the plane's image holds at p.
//
// Parameterised here by the curvature kappa = 1 / alpha, so that the collimated limit (alpha -> inf)
// is kappa = 0 and not an overflow, and a negative kappa describes a diverging bundle (a virtual
// focus behind the plane, as convex mirrors make), which the paper's alpha > 0 cannot. With
// g(r) = 1 / f(r) = kappa (1 + beta r), the ray from p = c + r u leaves along a - r g(r) u and meets
// the plane parallel to the light plane at height z at the signed radius s(r) = r (1 - z g(r)) on
// u's side: the case (i) and case (ii) equations of Section 2.2 are s(r) = rho and s(r) = -rho.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "core/math.h"

namespace causticbench::csl {

// The up to three radii of the rays that meet a point at height z above the plane and distance rho
// from the axis (Eqs. 2 and 3), each with the side of the axis it leaves from (+1: the point's side,
// case (i); -1: the opposite side, case (ii)). Only radii in (0, max_radius] are kept.
struct Radii {
  int count = 0;
  double radius[3] = {0.0, 0.0, 0.0};
  int side[3] = {0, 0, 0};
};

// The profile of a spot light along its axis: kappa, beta. Pure functions of (r, z); no image.
struct Profile {
  double kappa = 0.0;  // 1 / alpha, 1/m
  double beta = 0.0;   // 1/m, >= 0

  double g(double r) const { return kappa * (1.0 + beta * r); }
  // Signed radius at height z of the ray leaving radius r.
  double s(double r, double z) const { return r * (1.0 - z * g(r)); }
  // ds/dr at height z.
  double ds(double r, double z) const { return 1.0 - z * kappa - 2.0 * z * kappa * beta * r; }
  // Eq. 4: the area ratio sigma = |h h'| / r of the beam from radius r at height z (1 at z = 0). Its
  // limit at r -> 0 is (1 - z kappa)^2.
  double area_ratio(double r, double z) const;
  // Eqs. 2 and 3, solved in a form that stays exact as beta z kappa -> 0 (the quadratic degenerates
  // into the linear equation of beta = 0 or a collimated light) and as z -> 0.
  Radii radii(double z, double rho, double max_radius) const;
};

// An intensity image over the square [-half_size, half_size]^2 of the light plane, in the plane's
// (u, v) coordinates: flux per unit light-plane area (W/m^2 per W/m^2 of the light's irradiance),
// one or three channels, stored as float32 or as uint16 with one scale per channel.
class IntensityImage {
 public:
  enum class Precision { float32, uint16 };
  IntensityImage() = default;
  // `values`: size x size x channels floats, row-major, texel (i, j) centred at
  // (-half + (i + 0.5) w, -half + (j + 0.5) w), w = 2 half / size.
  IntensityImage(int size, int channels, float half_size, const std::vector<float>& values, Precision precision);
  // An image from its stored form (quantised() and scales() for uint16, floats() for float32), exactly
  // as it was: what the build cache reads back. std::invalid_argument when the parts do not fit.
  static IntensityImage from_stored(int size, int channels, float half_size, Precision precision, std::vector<float> floats,
                                    std::vector<uint16_t> quantised, std::vector<float> scales);

  int size() const { return size_; }
  int channels() const { return channels_; }
  float half_size() const { return half_size_; }
  Precision precision() const { return precision_; }
  // Bilinear lookup at plane coordinates (x, y); zero beyond the image's edge texels.
  void lookup(float x, float y, float* out) const;
  // The flux of the rays leaving radii [0, r] (all channels) of the bilinear image, from a table
  // over radius built at construction: what the on-axis integration reads.
  void flux_within(double r, double* out) const;
  // The largest radius the image covers (its corner).
  double max_radius() const { return half_size_ * 1.41421356237; }
  // A radius beyond which every lookup() is zero: the farthest non-zero texel's centre plus the
  // reach of the bilinear filter (a texel diagonal) and a texel diagonal more for the lookup's float
  // rounding; 0 for an all-zero image (a black spot light). What the CPU backend's cull bounds with.
  double support_radius() const { return support_radius_; }
  // Total flux per channel: the sum of the texels times their area.
  void total_flux(double* out) const;
  size_t memory_bytes() const;
  // The raw stored values (for the build cache) and the decoded one at a texel.
  const std::vector<uint16_t>& quantised() const { return quantised_; }
  const std::vector<float>& floats() const { return floats_; }
  const std::vector<float>& scales() const { return scales_; }
  float texel(int i, int j, int channel) const;
  // The values as floats, whatever the precision: what the constructor takes back.
  std::vector<float> decoded() const;
  // The tables flux_within() interpolates, per channel at radius k * max_radius() / radial_bins(),
  // k = 0..radial_bins(): the flux within that radius and the ring integral there (the Vulkan backend's copy).
  int radial_bins() const { return radial_bins_; }
  const std::vector<double>& radial_flux() const { return radial_; }
  const std::vector<double>& ring_integral() const { return ring_; }

 private:
  void build_radial_table();
  void find_support();

  int size_ = 0, channels_ = 1;
  float half_size_ = 0.0f;
  Precision precision_ = Precision::float32;
  std::vector<float> floats_;
  std::vector<uint16_t> quantised_;
  std::vector<float> scales_;  // uint16: per channel, value = q * scale
  double support_radius_ = 0.0;
  // Per channel at radius k * max_radius / bins, k = 0..bins: the flux within it, and the ring
  // integral there.
  int radial_bins_ = 0;
  std::vector<double> radial_, ring_;
};

enum class OnAxis { integrate, epsilon };

struct EvaluationSettings {
  bool intensity_correction = true;  // Eq. 4 (Fig. 6 compares on and off)
  OnAxis on_axis = OnAxis::integrate;
  double axis_epsilon = 1e-4;        // epsilon mode: points nearer the axis are moved out to it (scene units)
};

// The geometry of a caustic spot light in its object's build space: its light plane and profile.
struct SpotGeometry {
  Vec3 origin{0.0f};                 // c
  Vec3 axis{0.0f, 0.0f, 1.0f};       // a, unit
  Vec3 u{1.0f, 0.0f, 0.0f}, v{0.0f, 1.0f, 0.0f};  // the light plane's axes, with a a right-handed frame
  Profile profile;

  // Direction of the ray leaving plane offset (x, y) (plane coordinates), unit.
  Vec3 ray_direction(double x, double y) const;
};

// What evaluation reads of a spot light's image, so that one evaluation serves a stored image and the
// blend of up to three that an interpolated spot light reads (methods/csl/interpolation.h):
//   int channels() const;
//   double max_radius() const;                        no ray leaves the plane farther out
//   bool lookup(double x, double y, float* out) const; false, out untouched, beyond the image
//   void flux_within(double r, double* out) const;     the flux of the rays leaving radii [0, r]
//   double support_radius() const;                    lookup() reads zero beyond it
class StoredImage {
 public:
  explicit StoredImage(const IntensityImage& image) : image_(image) {}
  int channels() const { return image_.channels(); }
  double max_radius() const { return image_.max_radius(); }
  bool lookup(double x, double y, float* out) const {
    const double half = image_.half_size();
    if (std::fabs(x) > half || std::fabs(y) > half) return false;
    image_.lookup(static_cast<float>(x), static_cast<float>(y), out);
    return true;
  }
  void flux_within(double r, double* out) const { image_.flux_within(r, out); }
  double support_radius() const { return image_.support_radius(); }

 private:
  const IntensityImage& image_;
};

// Caustic irradiance at `point` on a surface with unit `normal` facing the side it is lit from, per
// unit light irradiance, added to out[0..channels). `footprint_radius`: radius of the disk the
// receiver point stands for (the pixel's footprint), used where that disk reaches the axis
// (OnAxis::integrate). `visible(direction, from)` says whether the ray that travels along unit
// `direction` from the light plane point `from` (both build space) reaches the point unblocked
// (`occlusion: shadow_rays`); AlwaysVisible where nothing is tested. Returns the number of rays
// that contributed.
struct AlwaysVisible {
  bool operator()(const glm::dvec3&, const glm::dvec3&) const { return true; }
};
template <class Image, class Visible>
int evaluate_spot_light(const SpotGeometry& light, const Image& image, const Vec3& point, const Vec3& normal,
                        float footprint_radius, const EvaluationSettings& settings, float* out, const Visible& visible);

// One caustic spot light, in its object's build space.
struct SpotLight : SpotGeometry {
  IntensityImage image;
  // Whether this light's image adds to the frame (a CSL kept only to complete an interpolation
  // triple does not; Section 4.3).
  bool adds = true;

  template <class Visible = AlwaysVisible>
  int evaluate(const Vec3& point, const Vec3& normal, float footprint_radius, const EvaluationSettings& settings,
               float* out, const Visible& visible = {}) const {
    return evaluate_spot_light(*this, StoredImage(image), point, normal, footprint_radius, settings, out, visible);
  }
};

// Sets u and v from the axis (a fixed choice, so that a light plane's image is reproducible).
void set_plane_axes(SpotGeometry& light);

}  // namespace causticbench::csl

#include "methods/csl/spot_light_evaluate.h"
