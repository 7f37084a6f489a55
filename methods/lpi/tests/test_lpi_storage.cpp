// lpi's storage (methods/lpi/): the track-length estimator against exact irradiance, the layouts'
// interpolation against smooth analytic fields within their stated error, memory against its
// formulas, the stored precisions, and the light-sample reads at the extremes.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "methods/common/grid_layout.h"
#include "methods/lpi/light_samples.h"
#include "methods/lpi/shell_layout.h"
#include "methods/common/stored_values.h"

using namespace causticbench;
using namespace causticbench::lpi;

namespace {

// Parallel segments on a regular lattice that covers the cube [-1, 1]^3 exactly, `per_cell` x
// `per_cell` rays through each cell's cross-section, travelling along `axis` (towards -axis when
// `negative`), each with the flux of irradiance E over its share of the area.
std::vector<double> lattice_irradiance(const GridLayout& grid, int per_cell, int axis, bool negative, double irradiance,
                                       Orientation orientation) {
  const int lines = grid.resolution() * per_cell;
  const float spacing = 2.0f / static_cast<float>(lines);
  const int channels = channel_count(orientation);
  std::vector<float> sums(grid.points() * channels, 0.0f);
  for (int i = 0; i < lines; ++i) {
    for (int j = 0; j < lines; ++j) {
      Vec3 origin(0.0f), direction(0.0f);
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      origin[u] = -1.0f + (static_cast<float>(i) + 0.5f) * spacing;
      origin[v] = -1.0f + (static_cast<float>(j) + 0.5f) * spacing;
      origin[axis] = negative ? 5.0f : -5.0f;
      direction[axis] = negative ? -1.0f : 1.0f;
      PathSegment segment{origin, direction, std::numeric_limits<float>::infinity(),
                          Color(static_cast<float>(irradiance * spacing * spacing))};
      grid.deposit(segment, orientation, sums.data());
    }
  }
  std::vector<double> values(sums.begin(), sums.end());
  grid.normalise(1.0, orientation, values.data());
  return values;
}

}  // namespace

// A uniform beam through an empty volume: every cell holds exactly E times the cosine between the
// beam and its normal facing the centre (zero for cells the beam travels towards the centre in).
TEST(LpiEstimator, GridTrackLengthIsExactInAUniformBeam) {
  const GridLayout grid(Vec3(0.0f), 1.0f, 8);
  const double irradiance = 2.5;
  const std::vector<double> values = lattice_irradiance(grid, 3, 1, true, irradiance, Orientation::paper);
  double worst = 0.0;
  for (int z = 0; z < 8; ++z) {
    for (int y = 0; y < 8; ++y) {
      for (int x = 0; x < 8; ++x) {
        const Vec3 direction = glm::normalize(grid.cell_center(x, y, z));
        const double expected = irradiance * std::max(0.0f, glm::dot(Vec3(0, -1, 0), direction));
        for (int c = 0; c < 3; ++c) {
          worst = std::max(worst, std::fabs(values[grid.index(x, y, z) * 3 + c] - expected));
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-5 * irradiance);
}

// The vector orientation stores -E times the beam direction in every cell, exactly.
TEST(LpiEstimator, GridVectorIrradianceIsExactInAUniformBeam) {
  const GridLayout grid(Vec3(0.0f), 1.0f, 4);
  const std::vector<double> values = lattice_irradiance(grid, 2, 0, false, 1.5, Orientation::vector);
  for (size_t cell = 0; cell < grid.points(); ++cell) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(values[cell * 9 + 3 * c + 0], -1.5, 1e-5);
      EXPECT_NEAR(values[cell * 9 + 3 * c + 1], 0.0, 1e-6);
      EXPECT_NEAR(values[cell * 9 + 3 * c + 2], 0.0, 1e-6);
    }
  }
}

// The shells' basis functions sum to one, so their integrals partition the ball's volume: angular
// ones sum to 4 pi, radial ones to R^3 / 3.
TEST(LpiEstimator, ShellBasisIntegralsPartitionTheBall) {
  for (int subdivision : {0, 2, 4}) {
    for (ShellSpacing spacing : {ShellSpacing::uniform, ShellSpacing::quadratic}) {
      const ShellLayout shells(Vec3(0.0f), 2.0f, 5, subdivision, spacing);
      double angular = 0.0, radial = 0.0;
      for (double a : shells.angular_integrals()) angular += a;
      for (double r : shells.radial_integrals()) radial += r;
      // The points are single precision: their triangles tile the sphere to rounding.
      EXPECT_NEAR(angular, 4.0 * kPiDouble, 1e-6) << subdivision;
      EXPECT_NEAR(radial, 8.0 / 3.0, 1e-6) << subdivision;
    }
  }
}

// Random lines of a uniform beam (fixed seed) through shells: every sample's estimate converges to
// E times its cosine. 400,000 lines through a ball of radius 1 with 3 shells of 42 vertices: the
// relative standard error per sample is at most about 1 % (inner shell, smallest support); the
// bound of 5 % on the mean absolute error of the lit samples is far outside chance.
TEST(LpiEstimator, ShellTrackLengthConvergesToTheBeamsIrradiance) {
  const ShellLayout shells(Vec3(0.0f), 1.0f, 3, 1, ShellSpacing::uniform);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  const int lines = 400000;
  const double irradiance = 1.0, area = 4.0;  // the lines cover the square [-1, 1]^2
  std::vector<float> sums(shells.points() * 3, 0.0f);
  const Vec3 beam = glm::normalize(Vec3(0.3f, -1.0f, 0.2f));
  Vec3 tangent, bitangent;
  orthonormal_basis(beam, tangent, bitangent);
  for (int i = 0; i < lines; ++i) {
    const Vec3 origin = -3.0f * beam + uniform(random) * tangent + uniform(random) * bitangent;
    shells.deposit(PathSegment{origin, beam, 10.0f, Color(static_cast<float>(irradiance * area / lines))}, Orientation::paper,
                   sums.data());
  }
  std::vector<double> values(sums.begin(), sums.end());
  shells.normalise(1.0, Orientation::paper, values.data());
  double error = 0.0;
  int lit = 0;
  for (size_t k = 0; k < shells.radii().size(); ++k) {
    for (size_t v = 0; v < shells.directions(); ++v) {
      const double expected = irradiance * std::max(0.0f, glm::dot(beam, shells.mesh().points()[v]));
      const double value = values[(k * shells.directions() + v) * 3];
      if (expected < 0.2) continue;  // near the terminator the basis straddles lit and unlit directions
      error += std::fabs(value - expected) / expected;
      ++lit;
    }
  }
  ASSERT_GT(lit, 20);
  EXPECT_LT(error / lit, 0.05);
}

// Interpolation: values set from a smooth field at the sample points read back within the layout's
// interpolation error. Grid: trilinear, |error| <= sum over axes of h^2 / 8 max|f_ii| = 3 h^2 / (8 s^2)
// for a Gaussian of width s. Shells: linear in r (h_r^2 / 8 max|f_rr|) and barycentric over faces
// whose chords are at most e r long (e^2 r^2 / 2 max|D^2 f|), so 1 / s^2 (h_r^2 / 8 + e^2 r^2 / 2).
TEST(LpiInterpolation, SmoothFieldsReadBackWithinTheStatedError) {
  const float width = 0.6f;
  auto field = [&](const Vec3& p) {
    const Vec3 d = p - Vec3(0.2f, -0.1f, 0.15f);
    return std::exp(-glm::dot(d, d) / (2.0f * width * width));
  };
  std::mt19937_64 random(3);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  const GridLayout grid(Vec3(0.0f), 1.0f, 24);
  std::vector<float> grid_values(grid.points());
  for (int z = 0; z < 24; ++z)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) grid_values[grid.index(x, y, z)] = field(grid.cell_center(x, y, z));
  const ShellLayout shells(Vec3(0.0f), 1.0f, 16, 4, ShellSpacing::uniform);
  std::vector<float> shell_values(shells.points());
  for (size_t k = 0; k < shells.radii().size(); ++k)
    for (size_t v = 0; v < shells.directions(); ++v)
      shell_values[k * shells.directions() + v] = field(shells.radii()[k] * shells.mesh().points()[v]);
  const float h = grid.cell_size();
  const double grid_bound = 3.0 * h * h / (8.0 * width * width);
  const double radial_step = 1.0 / 16.0, chord = 63.4 * kPiDouble / 180.0 / 16.0 * 1.2;  // level 4: edges up to 1.2 x 63.4 deg / 2^4
  for (int i = 0; i < 2000; ++i) {
    Vec3 p(uniform(random), uniform(random), uniform(random));
    if (glm::length(p) > 0.95f || glm::length(p) < 1.0f / 16.0f) continue;
    const float inside = h / 2.0f;  // beyond the outermost cell centres the grid holds its value
    if (std::fabs(p.x) < 1.0f - inside && std::fabs(p.y) < 1.0f - inside && std::fabs(p.z) < 1.0f - inside) {
      Stencil stencil = grid.stencil(p);
      double value = 0.0, weights = 0.0;
      for (int s = 0; s < stencil.count; ++s) {
        value += stencil.weights[s] * grid_values[stencil.points[s]];
        weights += stencil.weights[s];
      }
      EXPECT_NEAR(weights, 1.0, 1e-5);
      EXPECT_LE(std::fabs(value - field(p)), grid_bound) << "grid at " << p.x << " " << p.y << " " << p.z;
    }
    Stencil stencil = shells.stencil(p);
    double value = 0.0, weights = 0.0;
    for (int s = 0; s < stencil.count; ++s) {
      value += stencil.weights[s] * shell_values[stencil.points[s]];
      weights += stencil.weights[s];
    }
    const double r = glm::length(p);
    const double shell_bound = (radial_step * radial_step / 8.0 + chord * chord * r * r / 2.0) / (width * width);
    EXPECT_NEAR(weights, 1.0, 1e-5);
    EXPECT_LE(std::fabs(value - field(p)), shell_bound) << "shells at r " << r;
  }
}

// Memory: the values hold points x channels x bytes per light sample; the paper's Fig. 11 sizes are
// 12 shells of geodesic vertices at subdivision 2 to 6, three bytes each.
TEST(LpiMemory, FiguresMatchTheirFormulas) {
  const double paper_kib[] = {5.7, 22.5, 90.1, 360.0, 1440.0};
  for (int level = 2; level <= 6; ++level) {
    const ShellLayout shells(Vec3(0.0f), 1.0f, 12, level, ShellSpacing::uniform);
    const size_t vertices = 10 * (size_t{1} << (2 * level)) + 2;
    ASSERT_EQ(shells.points(), 12 * vertices);
    std::vector<float> values(shells.points() * 3, 0.5f);
    const StoredValues stored = StoredValues::encode(Precision::uint8, 3, false, shells.points(), values);
    EXPECT_EQ(stored.bytes_per_light_sample(), 12 * vertices * 3);
    // The paper's figures, rounded: within 0.5 %.
    EXPECT_NEAR(stored.bytes_per_light_sample() / 1024.0 / paper_kib[level - 2], 1.0, 0.005) << "subdivision " << level;
  }
  const GridLayout grid(Vec3(0.0f), 1.0f, 10);
  std::vector<float> values(grid.points() * 9 * 2, 0.25f);
  for (Precision precision : {Precision::uint8, Precision::float16, Precision::float32}) {
    const StoredValues stored = StoredValues::encode(precision, 9, true, grid.points(), values);
    EXPECT_EQ(stored.light_samples(), 2u);
    EXPECT_EQ(stored.bytes_per_light_sample(), 1000u * 9u * precision_bytes(precision));
    EXPECT_EQ(stored.memory_bytes(), 2 * stored.bytes_per_light_sample() + 2 * sizeof(float));
  }
}

// Each precision reads back within its own rounding: float32 exactly, float16 to 2^-11 relative,
// uint8 to half a step of the block's largest magnitude.
TEST(LpiMemory, PrecisionsReadBackWithinTheirRounding) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<float> uniform(-3.0f, 3.0f);
  std::vector<float> values(600);
  for (float& v : values) v = uniform(random);
  for (Precision precision : {Precision::uint8, Precision::float16, Precision::float32}) {
    const StoredValues stored = StoredValues::encode(precision, 3, true, 100, values);
    for (size_t sample = 0; sample < 2; ++sample) {
      const std::vector<float> decoded = stored.decode(sample);
      float largest = 0.0f;
      for (size_t i = 0; i < 300; ++i) largest = std::max(largest, std::fabs(values[sample * 300 + i]));
      for (size_t i = 0; i < 300; ++i) {
        const float original = values[sample * 300 + i];
        const float tolerance = precision == Precision::float32 ? 0.0f
                                : precision == Precision::float16 ? std::fabs(original) * 4.9e-4f + 6e-8f
                                                                  : 0.5001f * largest / 127.0f;
        EXPECT_LE(std::fabs(decoded[i] - original), tolerance) << precision_name(precision);
      }
    }
  }
  EXPECT_EQ(half_to_float(float_to_half(65504.0f)), 65504.0f);
  EXPECT_EQ(half_to_float(float_to_half(6.0e-8f)), 5.9604645e-8f);  // the smallest subnormal
  EXPECT_THROW(StoredValues::encode(Precision::float16, 3, false, 1, {1e6f, 0.0f, 0.0f}), std::runtime_error);
}

// Light reads at the extremes: a direction exactly on a sample reads that sample alone with weight
// exactly one; on an edge, two; antipodal to a sample, finite weights summing to one; the aligned
// blend's rotation takes the light onto each sample it reads.
TEST(LpiLightSamples, ReadsAtSamplesEdgesAndAntipodes) {
  for (int level : {0, 2, 6}) {
    const LightSampleSet set = geodesic_samples(level, SampleAt::vertices);
    ASSERT_EQ(set.directions.size(), 10 * (size_t{1} << (2 * level)) + 2);
    for (size_t i = 0; i < set.directions.size(); i += std::max<size_t>(1, set.directions.size() / 50)) {
      const LightReads reads = light_reads(set, set.directions[i], Blend::barycentric);
      ASSERT_EQ(reads.count, 1) << "level " << level << " sample " << i;
      EXPECT_EQ(reads.reads[0].sample, i);
      EXPECT_EQ(reads.reads[0].weight, 1.0f);
      EXPECT_EQ(light_reads(set, set.directions[i], Blend::nearest).reads[0].sample, i);
    }
    const auto& triangle = set.mesh->triangles()[0];
    const Vec3 edge = glm::normalize(set.directions[triangle[0]] + set.directions[triangle[1]]);
    const LightReads on_edge = light_reads(set, edge, Blend::aligned);
    float total = 0.0f;
    for (int r = 0; r < on_edge.count; ++r) {
      total += on_edge.reads[r].weight;
      const Vec3 turned = on_edge.reads[r].rotation * edge;
      EXPECT_NEAR(glm::length(turned - set.directions[on_edge.reads[r].sample]), 0.0f, 1e-5f);
    }
    EXPECT_EQ(on_edge.count, 2) << "level " << level;
    EXPECT_NEAR(total, 1.0f, 1e-6f);
    const LightReads antipode = light_reads(set, -set.directions[0], Blend::aligned);
    total = 0.0f;
    for (int r = 0; r < antipode.count; ++r) total += antipode.reads[r].weight;
    EXPECT_NEAR(total, 1.0f, 1e-6f);
  }
}

// A meridian set turns the light about the axis: a light at the azimuth of the meridian reads its
// samples unturned, and any azimuth reads the same samples with the same weights.
TEST(LpiLightSamples, MeridianReadsDependOnlyOnThePolarAngle) {
  const LightSampleSet set = meridian_samples(1, Vec3(0, 1, 0));
  ASSERT_EQ(set.directions.size(), 11u);
  const float polar = 0.7f;
  for (float azimuth : {0.0f, 1.0f, 2.5f, -3.0f}) {
    const Vec3 across = glm::cross(set.axis, set.meridian);
    const Vec3 direction = std::cos(polar) * set.axis +
                           std::sin(polar) * (std::cos(azimuth) * set.meridian + std::sin(azimuth) * across);
    const LightReads reads = light_reads(set, direction, Blend::barycentric);
    ASSERT_EQ(reads.count, 2);
    EXPECT_EQ(reads.reads[0].sample, 2u);  // 0.7 rad lies between samples 2 (0.628) and 3 (0.942)
    EXPECT_NEAR(reads.reads[0].weight, 1.0f - (0.7f - 0.6283185f) / 0.3141593f, 1e-5f);
    const Vec3 turned = reads.reads[0].rotation * direction;
    EXPECT_NEAR(glm::dot(turned, across), 0.0f, 1e-5f);  // in the meridian's plane
    EXPECT_GT(glm::dot(turned, set.meridian), 0.0f);     // on its half
  }
}
