#include "methods/prt/transfer.h"

#include <chrono>
#include <cmath>

#include <immintrin.h>

#include <glm/gtc/packing.hpp>

#include "core/parallel.h"
#include "core/tracer.h"
#include "methods/common/harmonic_lighting.h"
#include "methods/common/photon_tracks.h"

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

// A row of half floats widened into `out` (n values): eight at a time with F16C.
__attribute__((target("avx2,f16c"))) void widen_f16c(const uint16_t* row, size_t n, float* out) {
  size_t j = 0;
  for (; j + 8 <= n; j += 8)
    _mm256_storeu_ps(out + j, _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(row + j))));
  for (; j < n; ++j) out[j] = _cvtsh_ss(row[j]);
}

void widen(const uint16_t* row, size_t n, float* out) {
  if (has_f16c()) return widen_f16c(row, n, out);
  for (size_t j = 0; j < n; ++j) out[j] = glm::unpackHalf1x16(row[j]);
}

}  // namespace

std::vector<float> incident_field(const TransferField& field, const std::vector<double> lighting[3]) {
  const size_t n2 = field.coefficients(), cells = field.grid->points();
  std::vector<float> incident(cells * 3 * n2, 0.0f);
  float light[3][kMaxBands * kMaxBands];
  for (int c = 0; c < 3; ++c)
    for (size_t j = 0; j < n2; ++j) light[c][j] = static_cast<float>(lighting[c][j]);
  parallel_blocks(cells, 512, [&](size_t begin, size_t end, size_t) {
    for (size_t cell = begin; cell < end; ++cell) {
      const size_t first = cell * field.values_per_cell();
      float widened[kMaxBands * kMaxBands];
      float* out = incident.data() + cell * 3 * n2;
      for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < n2; ++i) {
          const size_t at = first + (static_cast<size_t>(c) * n2 + i) * n2;
          const float* row = widened;
          if (field.matrices.empty()) {
            widen(field.halves.data() + at, n2, widened);
          } else {
            row = field.matrices.data() + at;
          }
          float sum = 0.0f;
          for (size_t j = 0; j < n2; ++j) sum += row[j] * light[c][j];
          out[static_cast<size_t>(c) * n2 + i] = sum;
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
  const size_t n2 = field.coefficients();
  float coefficients[3 * kMaxBands * kMaxBands] = {};
  const Stencil stencil = grid.stencil(point);
  for (int corner = 0; corner < stencil.count; ++corner) {
    const float* values = incident.data() + static_cast<size_t>(stencil.points[corner]) * 3 * n2;
    for (size_t k = 0; k < 3 * n2; ++k) coefficients[k] += stencil.weights[corner] * values[k];
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
