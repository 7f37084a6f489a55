// The intensity image of a fitted spot light (Liu et al. 2008, Section 3.1.2): every bundle ray's
// energy splatted into the light plane at the point p where it crosses it, by an EWA splat (Zwicker et
// al. 2002): an elliptical Gaussian whose axes are delta / (d . a) along p - c and delta across it (the
// ray treated as a cylinder of radius delta, cut obliquely by the plane), convolved with the texel's
// reconstruction filter and normalised over the texels it touches, so that every ray's energy lands
// in the image exactly once.
//
// The paper's delta is three times the rays' spacing on the object, "large enough to avoid the gaps";
// a light plane the fit puts away from the object sees the rays spread wider than that (or, past a
// focus, closer). So each ray's delta here is splat_scale times the larger of the spacing on the
// object and its mean distance to its four nearest neighbours on the plane (nanoflann), at most ten
// times the former: the paper's value where the plane is at the object, and no gaps where it is not.
#pragma once

#include <cstdint>
#include <vector>

#include "methods/csl/object_rays.h"
#include "methods/csl/spot_light.h"

namespace causticbench::csl {

struct SplatSettings {
  double spacing = 0.0;       // scene units: the rays' spacing on the object
  double splat_scale = 3.0;  // delta in spacings (the paper: 3)
  int image_size = 0;  // texels per side; 0: the paper's choice per light of 128, 256 or 512 (texels of delta / 2 or finer, up to 512)
  IntensityImage::Precision precision = IntensityImage::Precision::uint16;
  int channels = 1;    // 1: luminance (achromatic objects), 3: RGB
};

// The image of `light` (its origin, axes and profile set) from the rays `members`.
IntensityImage splat_intensity(const std::vector<CausticRay>& rays, const std::vector<uint32_t>& members,
                               const SpotLight& light, const SplatSettings& settings);

// The side the paper would choose for an image of half size `half` at splat radius `delta` (the
// median of the rays').
int automatic_image_size(double half, double delta);

}  // namespace causticbench::csl
