// FLIP from ../shared/metrics/flip.md; section numbers below refer to it. One file past the 500 lines the
// project keeps to, on purpose: the pipeline in the specification's order, section by section (colour
// spaces, CSF filters, feature detection, the HDR exposures), which a split would scatter.
#include "metrics/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "core/parallel.h"

namespace causticbench {

namespace {

// Rows per parallel block: fixed, so the blocks (and the results) do not depend on the thread count.
constexpr size_t kRowsPerBlock = 8;

constexpr float kQc = 0.7f, kPc = 0.4f, kPt = 0.95f, kFeatureWidth = 0.082f, kQf = 0.5f;
constexpr float kWhite[3] = {0.950428545f, 1.0f, 1.088900371f};
constexpr float kInverseWhite[3] = {1.052156925f, 1.0f, 0.918357670f};

// One channel of an image, row-major.
struct Plane {
  int width = 0, height = 0;
  std::vector<float> v;
  Plane() = default;
  Plane(int w, int h) : width(w), height(h), v(static_cast<size_t>(w) * h, 0.0f) {}
  float* row(int y) { return v.data() + static_cast<size_t>(y) * width; }
  const float* row(int y) const { return v.data() + static_cast<size_t>(y) * width; }
};

template <typename Function>
void for_rows(int height, Function fn) {
  parallel_blocks(static_cast<size_t>(height), kRowsPerBlock, [&](size_t begin, size_t end, size_t) {
    for (size_t y = begin; y < end; ++y) fn(static_cast<int>(y));
  });
}

// fn(pixel index) for every pixel of a width x height image, rows in parallel.
template <typename Function>
void for_pixels(int width, int height, Function fn) {
  for_rows(height, [&](int y) {
    const size_t begin = static_cast<size_t>(y) * width;
    for (size_t i = begin; i < begin + width; ++i) fn(i);
  });
}

// dst[x] += w * src[x]. In blocks of 8 because GCC's -O2 vectoriser only takes loops whose trip count it
// knows; each element gets the same multiply and add either way.
inline void add_scaled(float* __restrict dst, const float* __restrict src, float w, int n) {
  int x = 0;
  for (; x + 8 <= n; x += 8)
    for (int j = 0; j < 8; ++j) dst[x + j] += w * src[x + j];
  for (; x < n; ++x) dst[x] += w * src[x];
}

// Both passes add the taps in the same order (offset -r .. r) for every pixel, border or not, so a
// constant image filters to an exactly constant one (flip.md section 8, property 3). Correlation rather
// than convolution: the kernels are symmetric, or (the first derivative) only enter through a magnitude.
void filter_x(const Plane& in, const std::vector<float>& kernel, Plane& out) {
  const int r = static_cast<int>(kernel.size() / 2), width = in.width;
  out = Plane(in.width, in.height);
  for_rows(in.height, [&](int y) {
    std::vector<float> padded(static_cast<size_t>(width) + 2 * r);
    const float* src = in.row(y);
    for (int x = -r; x < width + r; ++x) padded[x + r] = src[std::clamp(x, 0, width - 1)];
    float* dst = out.row(y);
    for (size_t k = 0; k < kernel.size(); ++k) add_scaled(dst, padded.data() + k, kernel[k], width);
  });
}

void filter_y(const Plane& in, const std::vector<float>& kernel, Plane& out) {
  const int r = static_cast<int>(kernel.size() / 2), width = in.width, height = in.height;
  out = Plane(in.width, in.height);
  for_rows(height, [&](int y) {
    float* dst = out.row(y);
    for (size_t k = 0; k < kernel.size(); ++k)
      add_scaled(dst, in.row(std::clamp(y + static_cast<int>(k) - r, 0, height - 1)), kernel[k], width);
  });
}

Plane separable(const Plane& in, const std::vector<float>& kx, const std::vector<float>& ky) {
  Plane temporary, out;
  filter_x(in, kx, temporary);
  filter_y(temporary, ky, out);
  return out;
}

// --- Colour (section 2) ---------------------------------------------------------------------------------

struct Triple {
  float a, b, c;
};

Triple rgb_to_xyz(Triple rgb) {
  return {(10135552.0f * rgb.a + 8788810.0f * rgb.b + 4435075.0f * rgb.c) / 24577794.0f,
          (2613072.0f * rgb.a + 8788810.0f * rgb.b + 887015.0f * rgb.c) / 12288897.0f,
          (1425312.0f * rgb.a + 8788810.0f * rgb.b + 70074185.0f * rgb.c) / 73733382.0f};
}

Triple xyz_to_rgb(Triple xyz) {
  return {3.241003275f * xyz.a - 1.537398934f * xyz.b - 0.498615861f * xyz.c,
          -0.969224334f * xyz.a + 1.875930071f * xyz.b + 0.041554224f * xyz.c,
          0.055639423f * xyz.a - 0.204011202f * xyz.b + 1.057148933f * xyz.c};
}

Triple xyz_to_ycxcz(Triple xyz) {
  const float x = xyz.a * kInverseWhite[0], y = xyz.b * kInverseWhite[1], z = xyz.c * kInverseWhite[2];
  return {116.0f * y - 16.0f, 500.0f * (x - y), 200.0f * (y - z)};
}

Triple ycxcz_to_xyz(Triple ycxcz) {
  const float y = (ycxcz.a + 16.0f) / 116.0f;
  const float x = y + ycxcz.b / 500.0f, z = y - ycxcz.c / 200.0f;
  return {x * kWhite[0], y * kWhite[1], z * kWhite[2]};
}

float lab_f(float t) {
  constexpr float delta = 6.0f / 29.0f;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
}

// CIELab followed by the Hunt adjustment (section 3, steps 4-5).
Triple xyz_to_hunt_lab(Triple xyz) {
  const float fx = lab_f(xyz.a * kInverseWhite[0]), fy = lab_f(xyz.b * kInverseWhite[1]),
              fz = lab_f(xyz.c * kInverseWhite[2]);
  const float L = 116.0f * fy - 16.0f, a = 500.0f * (fx - fy), b = 200.0f * (fy - fz);
  return {L, 0.01f * L * a, 0.01f * L * b};
}

float hyab(Triple p, Triple q) {
  const float da = p.b - q.b, db = p.c - q.c;
  return std::abs(p.a - q.a) + std::sqrt(da * da + db * db);
}

// Section 3, step 7: the lowest 40% of the colour range onto [0, 0.95], the rest onto [0.95, 1].
float redistribute(float distance, float cmax) {
  const float dE = std::pow(distance, kQc), knee = kPc * cmax;
  return dE < knee ? dE * kPt / knee : kPt + (dE - knee) / (cmax - knee) * (1.0f - kPt);
}

// --- Kernels (sections 3 and 4) ------------------------------------------------------------------------

struct CsfKernels {
  std::vector<float> y, cx, cz1, cz2;
};

float sum(const std::vector<float>& kernel) {
  float total = 0.0f;
  for (float w : kernel) total += w;
  return total;
}

void divide(std::vector<float>& kernel, float divisor) {
  for (float& w : kernel) w /= divisor;
}

// Taps scale * exp(-pi^2 x_i^2 / b), x_i = i / ppd degrees, i = -rs..rs.
std::vector<float> csf_gaussian(float ppd, float scale, float b) {
  std::vector<float> g;
  for (int i = -flip_spatial_radius(ppd); i <= flip_spatial_radius(ppd); ++i) {
    const float x = static_cast<float>(i) / ppd;
    g.push_back(scale * std::exp(-kPi * kPi * x * x / b));
  }
  return g;
}

CsfKernels csf_kernels(float ppd) {
  CsfKernels k{csf_gaussian(ppd, 1.0f * std::sqrt(kPi / 0.0047f), 0.0047f),
               csf_gaussian(ppd, 1.0f * std::sqrt(kPi / 0.0053f), 0.0053f),
               csf_gaussian(ppd, std::sqrt(34.1f * std::sqrt(kPi / 0.04f)), 0.04f),
               csf_gaussian(ppd, std::sqrt(13.5f * std::sqrt(kPi / 0.025f)), 0.025f)};
  divide(k.y, sum(k.y));
  divide(k.cx, sum(k.cx));
  // Cz is a sum of two Gaussians: each is separated on its own, and one common factor makes the 2D sum 1.
  const float s1 = sum(k.cz1), s2 = sum(k.cz2), norm = std::sqrt(s1 * s1 + s2 * s2);
  divide(k.cz1, norm);
  divide(k.cz2, norm);
  return k;
}

struct FeatureKernels {
  std::vector<float> g, d1, d2;
};

// Each derivative kernel is scaled so its positive taps sum to +1 and its negative taps to -1: the
// response to a full 0-to-1 step is then at most 1 per direction, so an edge magnitude is at most sqrt(2).
void balance(std::vector<float>& kernel) {
  float positive = 0.0f, negative = 0.0f;
  for (float w : kernel) (w > 0.0f ? positive : negative) += w;
  for (float& w : kernel) w = w > 0.0f ? w / positive : (w < 0.0f ? w / -negative : 0.0f);
}

FeatureKernels feature_kernels(float ppd) {
  const float sigma = 0.5f * kFeatureWidth * ppd;
  const int r = flip_feature_radius(ppd);
  FeatureKernels k;
  for (int i = -r; i <= r; ++i) {
    const float x = static_cast<float>(i);
    const float g = std::exp(-x * x / (2.0f * sigma * sigma));
    k.g.push_back(g);
    k.d1.push_back(-x * g);
    k.d2.push_back((x * x / (sigma * sigma) - 1.0f) * g);
  }
  divide(k.g, sum(k.g));
  balance(k.d1);
  balance(k.d2);
  return k;
}

// --- LDR-FLIP ------------------------------------------------------------------------------------------

void check_pair(const Image& reference, const Image& test, const char* what) {
  if (reference.width() != test.width() || reference.height() != test.height())
    throw std::invalid_argument(std::string(what) + ": the test image is " + std::to_string(test.width()) + "x" +
                                std::to_string(test.height()) + " but the reference is " +
                                std::to_string(reference.width()) + "x" + std::to_string(reference.height()));
  if (reference.channels() < 3 || test.channels() < 3)
    throw std::invalid_argument(std::string(what) + ": both images need at least 3 channels");
  if (reference.pixel_count() == 0) throw std::invalid_argument(std::string(what) + ": empty images");
}

using Planes = std::array<Plane, 3>;  // Y', Cx, Cz

Planes planes_of(const Image& image) {
  Planes p{Plane(image.width(), image.height()), Plane(image.width(), image.height()),
           Plane(image.width(), image.height())};
  for (size_t i = 0; i < image.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) p[c].v[i] = image.at(i, c);
  return p;
}

Planes csf_filter_planes(const Planes& in, const CsfKernels& k) {
  Planes out{separable(in[0], k.y, k.y), separable(in[1], k.cx, k.cx), separable(in[2], k.cz1, k.cz1)};
  Plane second = separable(in[2], k.cz2, k.cz2);
  for (size_t i = 0; i < out[2].v.size(); ++i) out[2].v[i] += second.v[i];
  return out;
}

// Per-image part of LDR-FLIP: Hunt-adjusted Lab of the filtered colours, and the feature magnitudes.
struct Prepared {
  Plane L, a, b, edge, point;
};

Prepared prepare(const Image& linear, const CsfKernels& csf, const FeatureKernels& features) {
  Planes ycxcz = planes_of(flip_linear_rgb_to_ycxcz(linear));
  Planes filtered = csf_filter_planes(ycxcz, csf);
  Prepared p;
  p.L = std::move(filtered[0]);
  p.a = std::move(filtered[1]);
  p.b = std::move(filtered[2]);
  for_pixels(linear.width(), linear.height(), [&](size_t i) {
    Triple rgb = xyz_to_rgb(ycxcz_to_xyz({p.L.v[i], p.a.v[i], p.b.v[i]}));
    rgb = {std::clamp(rgb.a, 0.0f, 1.0f), std::clamp(rgb.b, 0.0f, 1.0f), std::clamp(rgb.c, 0.0f, 1.0f)};
    Triple lab = xyz_to_hunt_lab(rgb_to_xyz(rgb));
    p.L.v[i] = lab.a;
    p.a.v[i] = lab.b;
    p.b.v[i] = lab.c;
  });
  // Features see the unfiltered achromatic channel, normalised to [0, 1].
  Plane v = std::move(ycxcz[0]);
  for (float& value : v.v) value = (value + 16.0f) / 116.0f;
  Plane gx, d1x, d2x;
  filter_x(v, features.g, gx);
  filter_x(v, features.d1, d1x);
  filter_x(v, features.d2, d2x);
  Plane ex, ey, px, py;
  filter_y(d1x, features.g, ex);
  filter_y(gx, features.d1, ey);
  filter_y(d2x, features.g, px);
  filter_y(gx, features.d2, py);
  p.edge = std::move(ex);
  p.point = std::move(px);
  for_pixels(linear.width(), linear.height(), [&](size_t i) {
    p.edge.v[i] = std::sqrt(p.edge.v[i] * p.edge.v[i] + ey.v[i] * ey.v[i]);
    p.point.v[i] = std::sqrt(p.point.v[i] * p.point.v[i] + py.v[i] * py.v[i]);
  });
  return p;
}

Image ldr_flip_of_clamped(const Image& reference, const Image& test, float ppd) {
  const CsfKernels csf = csf_kernels(ppd);
  const FeatureKernels features = feature_kernels(ppd);
  const Prepared r = prepare(reference, csf, features), t = prepare(test, csf, features);
  const float cmax = flip_cmax();
  Image map(reference.width(), reference.height(), 1);
  for_pixels(map.width(), map.height(), [&](size_t i) {
    const float ec = redistribute(hyab({r.L.v[i], r.a.v[i], r.b.v[i]}, {t.L.v[i], t.a.v[i], t.b.v[i]}), cmax);
    const float feature = std::max(std::abs(r.edge.v[i] - t.edge.v[i]), std::abs(r.point.v[i] - t.point.v[i]));
    const float ef = std::pow(feature / std::sqrt(2.0f), kQf);
    // Guarded because pow(0, 0) = 1 would turn a zero colour error with Ef = 1 into the maximum.
    map.at(i, 0) = ec == 0.0f ? 0.0f : std::pow(ec, 1.0f - ef);
  });
  return map;
}

// The first three channels, clamped to [0, 1].
Image clamped_rgb(const Image& image) {
  Image out(image.width(), image.height(), 3);
  for (size_t i = 0; i < image.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) out.at(i, c) = std::clamp(image.at(i, c), 0.0f, 1.0f);
  return out;
}

// --- HDR-FLIP (section 6) --------------------------------------------------------------------------------

const float* tone_coefficients(FlipToneMapper tone_mapper) {
  static const float aces[6] = {0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f, 0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f};
  static const float hable[6] = {0.231683f, 0.013791f, 0.0f, 0.18f, 0.3f, 0.018f};
  static const float reinhard[6] = {0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f};
  switch (tone_mapper) {
    case FlipToneMapper::aces: return aces;
    case FlipToneMapper::hable: return hable;
    case FlipToneMapper::reinhard: return reinhard;
  }
  throw std::logic_error("flip: unknown tone mapper");
}

float luminance(const Image& image, size_t pixel) {
  return 0.2126f * image.at(pixel, 0) + 0.7152f * image.at(pixel, 1) + 0.0722f * image.at(pixel, 2);
}

// The image exposed by 2^exposure, tone mapped and clamped to [0, 1].
Image expose(const Image& image, float exposure, FlipToneMapper tone_mapper) {
  const double scale = std::pow(2.0, static_cast<double>(exposure));
  const float* c = tone_coefficients(tone_mapper);
  Image out(image.width(), image.height(), 3);
  // In double, and the rational curve divided through by x^2 above 1: a legal E_c of 1e25 W/m^2 exposed
  // and squared overflows float (inf / inf is NaN, and a clamp keeps NaN, which scored as no error at all).
  for_pixels(image.width(), image.height(), [&](size_t i) {
    const double rgb[3] = {scale * image.at(i, 0), scale * image.at(i, 1), scale * image.at(i, 2)};
    const double reinhard_divisor = 1.0 + 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    for (int k = 0; k < 3; ++k) {
      const double x = rgb[k];
      double mapped;
      if (tone_mapper == FlipToneMapper::reinhard) {
        mapped = x / reinhard_divisor;
      } else if (x <= 1.0) {
        mapped = (c[0] * x * x + c[1] * x + c[2]) / (c[3] * x * x + c[4] * x + c[5]);
      } else {
        const double inverse = 1.0 / x;
        mapped = (c[0] + (c[1] + c[2] * inverse) * inverse) / (c[3] + (c[4] + c[5] * inverse) * inverse);
      }
      out.at(i, k) = static_cast<float>(std::isnan(mapped) ? 1.0 : std::clamp(mapped, 0.0, 1.0));
    }
  });
  return out;
}

// Upper median (index floor(n / 2) of the sorted values); `values` is reordered.
float upper_median(std::vector<float>& values) {
  auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

FlipExposureRange complete_range(float start, float stop, const FlipOptions& options) {
  if (options.start_exposure) start = *options.start_exposure;
  if (options.stop_exposure) stop = *options.stop_exposure;
  FlipExposureRange range{start, stop, 0};
  if (!std::isfinite(start) || !std::isfinite(stop)) return range;  // caller decides; N stays 0
  if (start > stop)
    throw std::invalid_argument("HDR-FLIP: the start exposure " + std::to_string(start) +
                                " exceeds the stop exposure " + std::to_string(stop));
  range.count = options.exposures ? *options.exposures
                                  : std::max(2, static_cast<int>(std::ceil(stop - start)));
  if (range.count < 2) throw std::invalid_argument("HDR-FLIP: needs at least 2 exposures");
  return range;
}

HdrFlipResult hdr_flip_with_range(const Image& reference, const Image& test, const FlipExposureRange& range,
                                  const FlipOptions& options) {
  HdrFlipResult result;
  result.exposures = range;
  result.error_map = Image(reference.width(), reference.height(), 1, 0.0f);
  result.exposure_map = Image(reference.width(), reference.height(), 1, 0.0f);
  const float step = (range.stop - range.start) / static_cast<float>(range.count - 1);
  for (int i = 0; i < range.count; ++i) {
    const float exposure = range.start + static_cast<float>(i) * step;
    Image map = ldr_flip_of_clamped(expose(reference, exposure, options.tone_mapper),
                                    expose(test, exposure, options.tone_mapper), options.pixels_per_degree);
    const float index = static_cast<float>(i) / static_cast<float>(range.count - 1);
    for (size_t p = 0; p < map.pixel_count(); ++p) {
      if (map.at(p, 0) > result.error_map.at(p, 0)) {
        result.error_map.at(p, 0) = map.at(p, 0);
        result.exposure_map.at(p, 0) = index;
      }
    }
  }
  return result;
}

}  // namespace

// --- Building blocks -------------------------------------------------------------------------------------

float flip_srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

int flip_spatial_radius(float ppd) {
  constexpr float b_max = 0.04f;
  return static_cast<int>(std::ceil(3.0f * std::sqrt(b_max / (2.0f * kPi * kPi)) * ppd));
}

int flip_feature_radius(float ppd) { return static_cast<int>(std::ceil(3.0f * 0.5f * kFeatureWidth * ppd)); }

float flip_cmax() {
  const Triple green = xyz_to_hunt_lab(rgb_to_xyz({0.0f, 1.0f, 0.0f}));
  const Triple blue = xyz_to_hunt_lab(rgb_to_xyz({0.0f, 0.0f, 1.0f}));
  return std::pow(hyab(green, blue), kQc);
}

float flip_tone_mapper_xmax(FlipToneMapper tone_mapper) {
  const float* c = tone_coefficients(tone_mapper);
  constexpr float target = 0.85f;
  const float A = c[0] - target * c[3], B = c[1] - target * c[4], C = c[2] - target * c[5];
  if (A == 0.0f) return -C / B;
  const float p = B / A, q = C / A;
  return -0.5f * p + std::sqrt(0.25f * p * p - q);
}

Image flip_linear_rgb_to_ycxcz(const Image& linear_rgb) {
  Image out(linear_rgb.width(), linear_rgb.height(), 3);
  for_pixels(linear_rgb.width(), linear_rgb.height(), [&](size_t i) {
    Triple v = xyz_to_ycxcz(rgb_to_xyz({linear_rgb.at(i, 0), linear_rgb.at(i, 1), linear_rgb.at(i, 2)}));
    out.set_rgb(i, Color(v.a, v.b, v.c));
  });
  return out;
}

Image flip_csf_filter(const Image& ycxcz, float ppd) {
  Planes f = csf_filter_planes(planes_of(ycxcz), csf_kernels(ppd));
  Image out(ycxcz.width(), ycxcz.height(), 3);
  for (size_t i = 0; i < out.pixel_count(); ++i) out.set_rgb(i, Color(f[0].v[i], f[1].v[i], f[2].v[i]));
  return out;
}

// --- Public FLIP ---------------------------------------------------------------------------------------

Image flip_error_map_ldr(const Image& reference, const Image& test, const FlipOptions& options) {
  check_pair(reference, test, "LDR-FLIP");
  return ldr_flip_of_clamped(clamped_rgb(reference), clamped_rgb(test), options.pixels_per_degree);
}

FlipExposureRange flip_exposure_range(const Image& reference, const FlipOptions& options) {
  const float xmax = flip_tone_mapper_xmax(options.tone_mapper);
  std::vector<float> lum(reference.pixel_count());
  for (size_t i = 0; i < lum.size(); ++i) lum[i] = luminance(reference, i);
  const float y_max = lum.empty() ? 0.0f : *std::max_element(lum.begin(), lum.end());
  const float y_median = lum.empty() ? 0.0f : upper_median(lum);
  return complete_range(std::log2(xmax / y_max), std::log2(xmax / y_median), options);
}

HdrFlipResult flip_error_map_hdr(const Image& reference, const Image& test, const FlipOptions& options) {
  check_pair(reference, test, "HDR-FLIP");
  const FlipExposureRange range = flip_exposure_range(reference, options);
  if (range.count == 0)
    throw std::invalid_argument("HDR-FLIP: the exposure range [" + std::to_string(range.start) + ", " +
                                std::to_string(range.stop) +
                                "] is not finite (the reference's maximum or median luminance is 0)");
  return hdr_flip_with_range(reference, test, range, options);
}

double flip_weighted_percentile(std::vector<float> values, double p) {
  std::sort(values.begin(), values.end());
  double total = 0.0;
  for (float v : values) total += v;
  double running = 0.0;
  for (float v : values) {
    running += v;
    if (running > p * total) return v;
  }
  return 0.0;
}

FlipPooled flip_pool(const Image& error_map, const std::vector<uint8_t>& mask) {
  std::vector<float> values;
  for (size_t i = 0; i < error_map.pixel_count(); ++i)
    if (mask.empty() || mask[i]) values.push_back(error_map.at(i, 0));
  FlipPooled pooled;
  pooled.pixels = values.size();
  if (values.empty()) return pooled;
  double total = 0.0;
  for (float v : values) total += v;
  pooled.mean = total / static_cast<double>(values.size());
  pooled.min = *std::min_element(values.begin(), values.end());
  pooled.max = *std::max_element(values.begin(), values.end());
  pooled.weighted_median = flip_weighted_percentile(values, 0.5);
  pooled.first_weighted_quartile = flip_weighted_percentile(values, 0.25);
  pooled.third_weighted_quartile = flip_weighted_percentile(values, 0.75);
  return pooled;
}

// --- The project's FLIP on E_c -------------------------------------------------------------------------

CausticFlip caustic_flip(const Image& test, const Image& reference, const std::vector<uint8_t>& mask,
                         const FlipOptions& options) {
  check_pair(reference, test, "flip");
  if (mask.size() != reference.pixel_count())
    throw std::invalid_argument("flip: the mask has " + std::to_string(mask.size()) + " entries for " +
                                std::to_string(reference.pixel_count()) + " pixels");
  const size_t n = reference.pixel_count();
  Image r(reference.width(), reference.height(), 3, 0.0f), t(reference.width(), reference.height(), 3, 0.0f);
  std::vector<uint8_t> valid(n, 0);
  CausticFlip result;
  float y_max = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    if (!mask[i]) continue;  // 0 in both: nothing outside the receivers reaches the filters
    bool finite = true;
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(reference.at(i, c)))
        throw std::invalid_argument("flip: the reference has a non-finite value at masked pixel " + std::to_string(i));
      finite = finite && std::isfinite(test.at(i, c));
    }
    for (int c = 0; c < 3; ++c) {
      r.at(i, c) = std::max(reference.at(i, c), 0.0f);
      if (finite) t.at(i, c) = std::max(test.at(i, c), 0.0f);
    }
    valid[i] = finite ? 1 : 0;
    result.pixels += valid[i];
    y_max = std::max(y_max, luminance(r, i));
  }
  if (result.pixels == 0) {
    result.undefined_reason = "no receiver pixel with a finite test value";
    return result;
  }
  if (!(y_max > 0.0f)) {
    result.undefined_reason =
        "the reference is 0 over the receivers: HDR-FLIP has no exposure range (its start is log2(xmax / 0))";
    return result;
  }
  // Section 10: the median of the lit receiver pixels, not of the whole image, which is 0 for most caustics.
  std::vector<float> lit;
  for (size_t i = 0; i < n; ++i)
    if (mask[i] && luminance(r, i) > static_cast<float>(kFlipLitFraction) * y_max) lit.push_back(luminance(r, i));
  const float xmax = flip_tone_mapper_xmax(options.tone_mapper);
  const FlipExposureRange range = complete_range(std::log2(xmax / y_max), std::log2(xmax / upper_median(lit)), options);
  if (range.count == 0) throw std::invalid_argument("flip: the exposure overrides are not finite");

  HdrFlipResult hdr = hdr_flip_with_range(r, t, range, options);
  result.exposures = range;
  result.error_map = std::move(hdr.error_map);
  double total = 0.0;
  for (size_t i = 0; i < n; ++i) {
    if (!mask[i]) result.error_map.at(i, 0) = 0.0f;
    if (valid[i]) total += result.error_map.at(i, 0);
  }
  result.mean = total / static_cast<double>(result.pixels);
  return result;
}

Image flip_error_map(const Image& test, const Image& reference, const std::vector<uint8_t>& mask) {
  return caustic_flip(test, reference, mask).error_map;
}

}  // namespace causticbench
