#include "methods/prt/transfer.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include <immintrin.h>

#include <glm/gtc/packing.hpp>

#include "core/parallel.h"
#include "core/tracer.h"
#include "methods/common/harmonic_lighting.h"
#include "methods/common/photon_tracks.h"
#include "methods/common/simd_lanes.h"

namespace causticbench::prt {

std::vector<Vec3> fibonacci_directions(int count) {
  std::vector<Vec3> directions;
  const double golden = kPiDouble * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / count;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = golden * k;
    directions.emplace_back(static_cast<float>(s * std::cos(phi)), static_cast<float>(s * std::sin(phi)), static_cast<float>(z));
  }
  return directions;
}

std::unique_ptr<GridLayout> transfer_grid(const BoundingSphere& bounds, const TransferSettings& settings) {
  const float radius = static_cast<float>(settings.volume_radius) * bounds.radius;
  return std::make_unique<GridLayout>(bounds.center, radius, settings.grid_resolution);
}

TransferField precompute_transfer(const Scene& build_scene, int object, const BoundingSphere& bounds,
                                  const TransferSettings& settings, const std::function<void(size_t, size_t)>& report) {
  const auto start = std::chrono::steady_clock::now();
  TransferField field;
  field.bands = settings.bands;
  field.grid = transfer_grid(bounds, settings);
  const GridLayout& grid = *field.grid;
  const size_t n2 = field.coefficients(), cells = grid.points(), per_cell = 3 * n2;
  field.matrices.assign(cells * field.values_per_cell(), 0.0f);
  SceneFrame frame(build_scene, 0.0);
  Tracer tracer(frame);
  PhotonTrackSums sums(cells * per_cell);
  const int bands = settings.bands;
  // A segment's radiance comes from -w_t: its basis values once per segment, then each cell it crosses.
  auto deposit = [&](const PathSegment& segment, float* values) {
    float basis[kMaxBands * kMaxBands];
    evaluate(bands, -segment.direction, basis);
    grid.walk(segment, [&](size_t cell, const int*, float length) {
      float* cell_values = values + cell * per_cell;
      for (int c = 0; c < 3; ++c) {
        const float weight = length * segment.power[c];
        float* channel = cell_values + static_cast<size_t>(c) * n2;
        for (size_t i = 0; i < n2; ++i) channel[i] += weight * basis[i];
      }
    });
  };
  const std::vector<Vec3> directions = fibonacci_directions(settings.source_directions);
  const double cell = grid.cell_size();
  const double photons = static_cast<double>(settings.photons_per_direction);
  const double normalise = 1.0 / (cell * cell * cell * photons);
  const double solid_angle = 4.0 * kPiDouble / static_cast<double>(directions.size());
  for (size_t s = 0; s < directions.size(); ++s) {
    PhotonLights lights;
    lights.add_directional(directions[s], Color(1.0f), 0.0);
    CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{settings.seed}, lights.frames(), {object});
    std::vector<double>& total =
        sums.accumulate(photon_tracer, static_cast<uint64_t>(s) << 32, settings.photons_per_direction, deposit, field.stats);
    // F(w_s) per colour: sqrt(4 pi) V sum_cells l_0 with l = total / (V photons), summed in cell order.
    for (int c = 0; c < 3; ++c) {
      double fluence = 0.0;
      for (size_t cell = 0; cell < cells; ++cell) fluence += total[cell * per_cell + static_cast<size_t>(c) * n2];
      field.direction_response.push_back(fluence * std::sqrt(4.0 * kPiDouble) / photons);
    }
    double source[kMaxBands * kMaxBands];
    evaluate(bands, glm::dvec3(directions[s]), source);
    // M_ij += l_i Y_j(w_s) 4 pi / N, cells in parallel (each its own rows); cells the beam missed skipped.
    parallel_blocks(cells, 256, [&](size_t begin, size_t end, size_t) {
      for (size_t c = begin; c < end; ++c) {
        const double* incident = total.data() + c * per_cell;
        bool any = false;
        for (size_t k = 0; k < per_cell && !any; ++k) any = incident[k] != 0.0;
        if (!any) continue;
        float* matrix = field.matrices.data() + c * field.values_per_cell();
        for (size_t row = 0; row < per_cell; ++row) {  // row = colour x incident coefficient
          const double l = incident[row] * normalise * solid_angle;
          if (l == 0.0) continue;
          float* out = matrix + row * n2;
          for (size_t j = 0; j < n2; ++j) out[j] += static_cast<float>(l * source[j]);
        }
      }
    });
    if (report) report(s + 1, directions.size());
  }
  if (settings.half) store_as_halves(field);
  field.shoot_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return field;
}

void store_as_halves(TransferField& field) {
  field.halves.resize(field.matrices.size());
  parallel_blocks(field.matrices.size(), 1 << 16, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) field.halves[i] = glm::packHalf1x16(field.matrices[i]);
  });
  std::vector<float>().swap(field.matrices);
}

namespace {

bool has_f16c() {
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("f16c");
  return available;
}

// Without F16C (and so without AVX2): one by one.
void widen(const uint16_t* row, size_t n, float* out) {
  for (size_t j = 0; j < n; ++j) out[j] = glm::unpackHalf1x16(row[j]);
}

// The product's dot product in eight partial sums, s_r over j = r mod 8 in j's order, folded as
// ((s0 + s4) + (s2 + s6)) + ((s1 + s5) + (s3 + s7)): the order AVX2's lanes sum in, which the scalar
// version (processors without AVX2) and shaders/product.comp repeat, so that every processor sums alike.
float dot_in_eight(const float* row, const float* light, size_t n) {
  float s[8] = {};
  for (size_t j = 0; j < n; ++j) s[j & 7] += row[j] * light[j];
  const float t[4] = {s[0] + s[4], s[1] + s[5], s[2] + s[6], s[3] + s[7]};
  return (t[0] + t[2]) + (t[1] + t[3]);
}

// `light` holds n rounded up to 8 floats, zeros after n; the row's lanes beyond n are masked (not read).
CAUSTICBENCH_AVX2 float dot_in_eight_avx2(const float* row, const float* light, size_t n) {
  __m256 s = _mm256_setzero_ps();
  size_t j = 0;
  for (; j + 8 <= n; j += 8) s = _mm256_add_ps(s, _mm256_mul_ps(_mm256_loadu_ps(row + j), _mm256_loadu_ps(light + j)));
  if (j < n) {
    const int left = static_cast<int>(n - j);
    const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i mask = _mm256_cmpgt_epi32(_mm256_set1_epi32(left), lanes);
    s = _mm256_add_ps(s, _mm256_mul_ps(_mm256_maskload_ps(row + j, mask), _mm256_loadu_ps(light + j)));
  }
  const __m128 t = _mm_add_ps(_mm256_castps256_ps128(s), _mm256_extractf128_ps(s, 1));  // s_r + s_(r+4)
  const __m128 u = _mm_add_ps(t, _mm_movehl_ps(t, t));                                    // t0 + t2, t1 + t3
  return _mm_cvtss_f32(_mm_add_ss(u, _mm_shuffle_ps(u, u, 1)));
}

// The same over a row of half floats, widened in the lanes (F16C): the same floats as widening first.
__attribute__((target("avx2,f16c"))) float dot_in_eight_f16c(const uint16_t* row, const float* light, size_t n) {
  __m256 s = _mm256_setzero_ps();
  size_t j = 0;
  for (; j + 8 <= n; j += 8) {
    const __m256 entries = _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + j)));
    s = _mm256_add_ps(s, _mm256_mul_ps(entries, _mm256_loadu_ps(light + j)));
  }
  if (j < n) {
    // The tail: the row's last eight entries (within it when n >= 8) moved down to lanes 0 .. left - 1, the
    // rest zeroed; a shorter row through a zeroed copy. (A copy costs a failed store forwarding a row.)
    const int left = static_cast<int>(n - j);
    __m256 entries;
    if (n >= 8) {
      const __m256 last = _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + n - 8)));
      const __m256i lanes = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
      const __m256i moved = _mm256_add_epi32(lanes, _mm256_set1_epi32(8 - left));
      const __m256 keep = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(left), lanes));
      entries = _mm256_and_ps(_mm256_permutevar8x32_ps(last, moved), keep);
    } else {
      uint16_t tail[8] = {};
      for (size_t k = j; k < n; ++k) tail[k - j] = row[k];
      entries = _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(tail)));
    }
    s = _mm256_add_ps(s, _mm256_mul_ps(entries, _mm256_loadu_ps(light + j)));
  }
  const __m128 t = _mm_add_ps(_mm256_castps256_ps128(s), _mm256_extractf128_ps(s, 1));
  const __m128 u = _mm_add_ps(t, _mm_movehl_ps(t, t));
  return _mm_cvtss_f32(_mm_add_ss(u, _mm_shuffle_ps(u, u, 1)));
}

// The lookup's trilinear sum of `count` (a multiple of 8) coefficients: per coefficient, the corners in
// order, each weight times value added to the sum so far (the scalar order, lane by lane).
void blend_corners(const Stencil& stencil, const float* incident, size_t stride, float* out) {
  for (size_t k = 0; k < stride; ++k) out[k] = 0.0f;
  for (int corner = 0; corner < stencil.count; ++corner) {
    const float* values = incident + static_cast<size_t>(stencil.points[corner]) * stride;
    for (size_t k = 0; k < stride; ++k) out[k] += stencil.weights[corner] * values[k];
  }
}

CAUSTICBENCH_AVX2 void blend_corners_avx2(const Stencil& stencil, const float* incident, size_t stride, float* out) {
  for (size_t k = 0; k < stride; k += 8) {
    __m256 sum = _mm256_setzero_ps();
    for (int corner = 0; corner < stencil.count; ++corner) {
      const float* values = incident + static_cast<size_t>(stencil.points[corner]) * stride + k;
      sum = _mm256_add_ps(sum, _mm256_mul_ps(_mm256_set1_ps(stencil.weights[corner]), _mm256_loadu_ps(values)));
    }
    _mm256_storeu_ps(out + k, sum);
  }
}

}  // namespace

float lane_dot(const float* row, const float* light, size_t n, bool lanes) {
  return lanes ? dot_in_eight_avx2(row, light, n) : dot_in_eight(row, light, n);
}

float lane_dot(const uint16_t* row, const float* light, size_t n, bool lanes) {
  if (lanes) return dot_in_eight_f16c(row, light, n);
  float widened[kMaxBands * kMaxBands];
  widen(row, n, widened);
  return dot_in_eight(widened, light, n);
}

std::vector<float> incident_field(const TransferField& field, const std::vector<float>& lighting) {
  const size_t n2 = field.coefficients(), cells = field.grid->points(), stride = field.incident_stride();
  if (lighting.size() != 3 * n2) throw std::invalid_argument("prt::incident_field: the lighting is not 3 x bands^2 floats");
  std::vector<float> incident(cells * stride, 0.0f);
  // Each colour's lighting padded with zeros to whole lanes.
  float light[3][kMaxBands * kMaxBands + 8] = {};
  for (int c = 0; c < 3; ++c)
    for (size_t j = 0; j < n2; ++j) light[c][j] = lighting[static_cast<size_t>(c) * n2 + j];
  const bool avx2 = simd::has_avx2(), f16c = has_f16c();
  parallel_blocks(cells, 512, [&](size_t begin, size_t end, size_t) {
    float widened[kMaxBands * kMaxBands + 8] = {};
    for (size_t cell = begin; cell < end; ++cell) {
      const size_t first = cell * field.values_per_cell();
      float* out = incident.data() + cell * stride;
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < n2; ++i) {
          const size_t at = first + (static_cast<size_t>(c) * n2 + i) * n2;
          float& result = out[static_cast<size_t>(c) * n2 + i];
          if (field.matrices.empty()) {
            if (f16c) {
              result = dot_in_eight_f16c(field.halves.data() + at, light[c], n2);
            } else {
              widen(field.halves.data() + at, n2, widened);
              result = dot_in_eight(widened, light[c], n2);
            }
          } else {
            const float* row = field.matrices.data() + at;
            result = avx2 ? dot_in_eight_avx2(row, light[c], n2) : dot_in_eight(row, light[c], n2);
          }
        }
    }
  });
  return incident;
}

Color transfer_irradiance(const TransferField& field, const std::vector<float>& incident, const Vec3& point, const Vec3& normal) {
  const GridLayout& grid = *field.grid;
  const Vec3 offset = point - grid.center();
  const float half = grid.radius();
  if (std::abs(offset.x) > half || std::abs(offset.y) > half || std::abs(offset.z) > half) return Color(0.0f);
  const size_t n2 = field.coefficients(), stride = field.incident_stride();
  float coefficients[3 * kMaxBands * kMaxBands + 8];
  const Stencil stencil = grid.stencil(point);
  if (simd::has_avx2()) {
    blend_corners_avx2(stencil, incident.data(), stride, coefficients);
  } else {
    blend_corners(stencil, incident.data(), stride, coefficients);
  }
  float basis[kMaxBands * kMaxBands];
  evaluate(field.bands, normal, basis);
  Color result(0.0f);
  for (int l = 0; l < field.bands; ++l) {
    const float cosine = static_cast<float>(clamped_cosine(l));
    if (cosine == 0.0f) continue;
    for (int m = -l; m <= l; ++m) {
      const size_t k = static_cast<size_t>(coefficient_index(l, m));
      for (int c = 0; c < 3; ++c) result[c] += cosine * coefficients[static_cast<size_t>(c) * n2 + k] * basis[k];
    }
  }
  // A truncated series rings below zero beside a sharp light; irradiance is not negative: clamped, as
  // PRT renderers clamp what they display.
  return glm::max(result, Color(0.0f));
}

}  // namespace causticbench::prt
