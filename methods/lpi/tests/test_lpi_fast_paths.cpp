// lpi's fast paths (issue 11) against the straightforward code they replaced, bit for bit: the grid's
// DDA deposit (per-axis offset tables, cells of cosine zero skipped) against a DDA that computes
// every cell's centre and direction, and the per-pixel lookup (one stencil shared by the unrotated
// reads, decoding fixed at compile time) against reading each light sample through its own stencil
// and StoredValues::add. Equal bits, not a tolerance: the stored builds and the Vulkan kernel's
// agreement (test_lpi_vulkan.cpp) rest on the arithmetic being unchanged.
#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>

#include <gtest/gtest.h>

#include "core/parallel.h"
#include "methods/common/simd_lanes.h"
#include "methods/lifecycle.h"
#include "store/build_cache.h"
#include "methods/common/grid_layout.h"
#include "methods/lpi/lookup.h"
#include "methods/lpi/multires_layout.h"
#include "methods/lpi/shell_layout.h"
#include "methods/method_runner.h"

using namespace causticbench;
using namespace causticbench::lpi;

namespace {

// Amanatides & Woo as written before the fast path: each cell's centre and direction from
// cell_center(), the track added whatever its cosine.
void reference_deposit(const GridLayout& grid, const PathSegment& segment, Orientation orientation, float* sums) {
  const int channels = channel_count(orientation);
  const int resolution = grid.resolution();
  const float cell = grid.cell_size();
  const Vec3 minimum = grid.center() - Vec3(grid.radius());
  const Vec3 maximum = minimum + Vec3(2.0f * grid.radius());
  float t_enter = 0.0f, t_exit = segment.length;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = segment.direction[axis], o = segment.origin[axis];
    if (d == 0.0f) {
      if (o < minimum[axis] || o >= maximum[axis]) return;
      continue;
    }
    float t0 = (minimum[axis] - o) / d, t1 = (maximum[axis] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_exit = std::min(t_exit, t1);
  }
  if (!(t_exit > t_enter)) return;
  int index[3], step[3];
  float t_next[3], t_delta[3];
  const Vec3 start = segment.origin + segment.direction * t_enter;
  for (int axis = 0; axis < 3; ++axis) {
    const float d = segment.direction[axis];
    index[axis] = std::clamp(static_cast<int>(std::floor((start[axis] - minimum[axis]) / cell)), 0, resolution - 1);
    if (d > 0.0f) {
      step[axis] = 1;
      t_delta[axis] = cell / d;
      t_next[axis] = (minimum[axis] + (index[axis] + 1) * cell - segment.origin[axis]) / d;
    } else if (d < 0.0f) {
      step[axis] = -1;
      t_delta[axis] = -cell / d;
      t_next[axis] = (minimum[axis] + index[axis] * cell - segment.origin[axis]) / d;
    } else {
      step[axis] = 0;
      t_delta[axis] = t_next[axis] = std::numeric_limits<float>::infinity();
    }
  }
  float t = t_enter;
  while (t < t_exit) {
    const int axis = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    const float t_end = std::min(t_next[axis], t_exit);
    if (t_end > t) {
      const Vec3 to_cell = grid.cell_center(index[0], index[1], index[2]) - grid.center();
      const float distance = glm::length(to_cell);
      const Vec3 sample_direction = distance > 0.0f ? to_cell / distance : Vec3(0.0f);
      add_track(segment, t_end - t, sample_direction, orientation,
                sums + grid.index(index[0], index[1], index[2]) * static_cast<size_t>(channels));
    }
    t = t_end;
    if (t >= t_exit) break;
    index[axis] += step[axis];
    if (index[axis] < 0 || index[axis] >= resolution) break;
    t_next[axis] += t_delta[axis];
  }
}

// Segments of every kind the photon tracer makes: from inside and outside the cube, along axes (zero
// direction components), through the centre, finite and endless.
std::vector<PathSegment> random_segments(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f), unit(0.0f, 1.0f);
  std::normal_distribution<float> gaussian;
  std::vector<PathSegment> segments;
  for (int i = 0; i < count; ++i) {
    PathSegment segment;
    segment.origin = Vec3(coordinate(random), coordinate(random), coordinate(random));
    Vec3 direction(gaussian(random), gaussian(random), gaussian(random));
    if (i % 7 == 1) direction[i % 3] = 0.0f;
    if (i % 11 == 2) direction = Vec3(0.0f), direction[i % 3] = i % 2 ? 1.0f : -1.0f;
    if (i % 13 == 3) direction = -segment.origin;  // through the centre
    segment.direction = glm::normalize(direction);
    segment.length = i % 3 == 0 ? std::numeric_limits<float>::infinity() : 4.0f * unit(random);
    segment.power = Color(unit(random), unit(random), unit(random));
    segments.push_back(segment);
  }
  return segments;
}

}  // namespace

TEST(LpiFastPaths, GridDepositEqualsTheStraightDda) {
  const std::vector<PathSegment> segments = random_segments(3000, 5);
  for (int resolution : {1, 2, 5, 16}) {
    for (Orientation orientation : {Orientation::paper, Orientation::vector}) {
      const GridLayout grid(Vec3(0.1f, -0.2f, 0.05f), 1.3f, resolution);
      const size_t count = grid.points() * static_cast<size_t>(channel_count(orientation));
      std::vector<float> fast(count, 0.0f), reference(count, 0.0f);
      for (const PathSegment& segment : segments) {
        grid.deposit(segment, orientation, fast.data());
        reference_deposit(grid, segment, orientation, reference.data());
      }
      size_t different = 0, nonzero = 0;
      for (size_t i = 0; i < count; ++i) {
        different += std::memcmp(&fast[i], &reference[i], sizeof(float)) != 0;
        nonzero += reference[i] != 0.0f;
      }
      EXPECT_EQ(different, 0u) << "resolution " << resolution << ", orientation "
                               << (orientation == Orientation::paper ? "paper" : "vector");
      EXPECT_GT(nonzero, count / 4) << "the segments should cross most cells";
    }
  }
}

namespace {

// The lookup as written before the fast path: each read through its own stencil, each value through
// StoredValues::add, the layout reached through VolumeLayout.
void reference_caustic(const VolumeLayout& layout, const ObjectView& view, const GBuffer& gbuffer, Image& result) {
  const Vec3 center = layout.center();
  const float radius = layout.radius();
  const bool vector = view.values.channels() == 9;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    const Vec3 point = view.map.point(gbuffer.position[pixel]);
    const Vec3 normal = glm::normalize(view.map.normals * gbuffer.normal[pixel]);
    Vec3 offset = point - center;
    const float distance = glm::length(offset);
    float fade = 1.0f;
    if (distance > radius) {
      if (view.outside == Outside::zero) continue;
      if (view.outside == Outside::fade) fade = (radius / distance) * (radius / distance);
      offset *= radius / distance;
    }
    const float paper_cosine = distance > 0.0f ? std::max(0.0f, -glm::dot(normal, point - center) / distance) : 0.0f;
    Color total(0.0f);
    for (size_t l = 0; l < view.light_count; ++l) {
      const LightView& light = view.lights[l];
      float sums[3] = {0.0f, 0.0f, 0.0f};
      for (int r = 0; r < light.reads.count; ++r) {
        const SampleRead& read = light.reads.reads[r];
        const Stencil stencil = layout.stencil(center + (read.rotated ? read.rotation * offset : offset));
        float values[9] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
        for (int s = 0; s < stencil.count; ++s) {
          view.values.add(read.sample, stencil.points[s], stencil.weights[s] * read.weight, values);
        }
        add_shading(values, read.rotated ? read.rotation * normal : normal, vector, paper_cosine, sums);
      }
      for (int c = 0; c < 3; ++c) total[c] += std::max(0.0f, sums[c]) * light.irradiance[c] * fade;
    }
    const Color before(result.at(pixel, 0), result.at(pixel, 1), result.at(pixel, 2));
    result.set_rgb(pixel, before + total);
  }
}

// Receiver points in and beyond the ball (radius about 1 about the origin), some masked out.
GBuffer random_receivers(int width, int height, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> coordinate(-0.95f, 0.95f);
  std::normal_distribution<float> gaussian;
  GBuffer gbuffer;
  gbuffer.width = width;
  gbuffer.height = height;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    gbuffer.position.emplace_back(coordinate(random), coordinate(random), coordinate(random));
    gbuffer.normal.push_back(glm::normalize(Vec3(gaussian(random), gaussian(random), gaussian(random))));
    gbuffer.receiver.push_back(pixel % 9 == 4 ? 0 : 1);
  }
  return gbuffer;
}

// Light samples' values with a scale per sample (uint8 steps differ), non-negative for the paper
// orientation, of both signs for the vector one.
std::vector<float> random_values(size_t samples, size_t points, int channels, bool signed_channels, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(signed_channels ? -1.0f : 0.0f, 1.0f);
  std::vector<float> values(samples * points * static_cast<size_t>(channels));
  for (size_t i = 0; i < values.size(); ++i) values[i] = unit(random) * static_cast<float>(1 + (i / (points * channels)) % 4);
  return values;
}

SampleRead read_of(uint32_t sample, float weight, const glm::mat3* rotation = nullptr) {
  return SampleRead{sample, weight, rotation != nullptr, rotation ? *rotation : glm::mat3(1.0f)};
}

// Every blend's shape of reads: nearest (one), barycentric (three, or two on an edge), aligned (three
// rotated, or one of them at the light itself), and two lights at once.
std::vector<std::vector<LightView>> light_cases() {
  const glm::mat3 turn_a = rotation_between(glm::normalize(Vec3(0.2f, 1.0f, 0.1f)), Vec3(0.0f, 1.0f, 0.0f));
  const glm::mat3 turn_b = rotation_between(glm::normalize(Vec3(-0.4f, 1.0f, 0.3f)), Vec3(0.0f, 1.0f, 0.0f));
  auto light = [](std::vector<SampleRead> reads, Color irradiance) {
    LightView view;
    view.irradiance = irradiance;
    view.reads.count = static_cast<int>(reads.size());
    for (size_t r = 0; r < reads.size(); ++r) view.reads.reads[r] = reads[r];
    return view;
  };
  const Color white(1.0f), warm(2.0f, 1.5f, 0.5f);
  return {
      {light({read_of(2, 1.0f)}, white)},
      {light({read_of(0, 0.2f), read_of(3, 0.5f), read_of(1, 0.3f)}, warm)},
      {light({read_of(1, 0.6f), read_of(2, 0.4f)}, white)},
      {light({read_of(0, 0.2f, &turn_a), read_of(3, 0.5f, &turn_b), read_of(1, 0.3f, &turn_a)}, warm)},
      {light({read_of(0, 0.25f), read_of(3, 0.5f, &turn_b), read_of(1, 0.25f, &turn_a)}, white)},
      {light({read_of(0, 0.2f), read_of(3, 0.5f), read_of(1, 0.3f)}, warm), light({read_of(2, 1.0f)}, white),
       light({read_of(1, 0.7f, &turn_a), read_of(0, 0.3f)}, warm)},
  };
}

// Every storage, blend shape and `outside` through add_object_caustic (on a grid of resolution 2 or
// more, the AVX2 lanes where the processor has them and no read is rotated) and through the scalar
// lookup alone, each against the reference. Returns how many cases the lanes took.
template <class Layout>
int expect_lookup_equals_reference(const Layout& layout, const char* name) {
  int lane_cases = 0;
  const GBuffer gbuffer = random_receivers(23, 17, 3);
  BuildSpaceMap map;
  // A turn and a scale, as an object's pose gives (normals are normalised after, so a turn serves).
  map.normals = rotation_between(glm::normalize(Vec3(0.3f, 1.0f, 0.2f)), Vec3(0.0f, 1.0f, 0.0f));
  map.linear = 1.1f * map.normals;
  map.offset = Vec3(0.05f, -0.1f, 0.02f);
  const size_t samples = 4;
  struct Storage {
    Precision precision;
    Orientation orientation;
  };
  const Storage storages[] = {{Precision::float32, Orientation::paper}, {Precision::float16, Orientation::paper},
                              {Precision::uint8, Orientation::paper},   {Precision::float32, Orientation::vector},
                              {Precision::float16, Orientation::vector}, {Precision::uint8, Orientation::vector}};
  for (const Storage& storage : storages) {
    const int channels = channel_count(storage.orientation);
    const bool signed_channels = storage.orientation == Orientation::vector;
    const StoredValues values = StoredValues::encode(
        storage.precision, channels, signed_channels, layout.points(),
        random_values(samples, layout.points(), channels, signed_channels, 11));
    const std::vector<std::vector<LightView>> cases = light_cases();
    for (size_t c = 0; c < cases.size(); ++c) {
      for (Outside outside : {Outside::clamp, Outside::fade, Outside::zero}) {
        const ObjectView view{values, map, cases[c].data(), cases[c].size(), outside};
        Image fast(gbuffer.width, gbuffer.height, 3, 0.25f), scalar(gbuffer.width, gbuffer.height, 3, 0.25f),
            reference(gbuffer.width, gbuffer.height, 3, 0.25f);
        add_object_caustic(layout, view, gbuffer, 0, gbuffer.pixel_count(), fast);
        add_object_caustic_scalar(layout, view, gbuffer, 0, gbuffer.pixel_count(), scalar);
        reference_caustic(layout, view, gbuffer, reference);
        if constexpr (std::is_same_v<Layout, GridLayout>) lane_cases += grid_lanes_apply(layout, view);
        size_t different = 0, different_scalar = 0, lit = 0;
        for (size_t i = 0; i < fast.values().size(); ++i) {
          different += std::memcmp(&fast.values()[i], &reference.values()[i], sizeof(float)) != 0;
          different_scalar += std::memcmp(&scalar.values()[i], &reference.values()[i], sizeof(float)) != 0;
          lit += reference.values()[i] != 0.25f;
        }
        EXPECT_EQ(different, 0u) << name << ", " << precision_name(storage.precision) << ", "
                                 << (signed_channels ? "vector" : "paper") << ", light case " << c;
        EXPECT_EQ(different_scalar, 0u) << name << " (scalar), " << precision_name(storage.precision) << ", "
                                        << (signed_channels ? "vector" : "paper") << ", light case " << c;
        EXPECT_GT(lit, fast.values().size() / 8) << name << ": the case should light many pixels";
      }
    }
  }
  return lane_cases;
}

}  // namespace

TEST(LpiFastPaths, GridLookupEqualsReadingEachSampleAlone) {
  const int lane_cases = expect_lookup_equals_reference(GridLayout(Vec3(0.0f), 1.0f, 7), "grid 7");
  // Six storages x three `outside` x the three unrotated light cases (nearest, barycentric, edge).
  std::vector<float> probe;
  const bool lanes = decode_in_lanes(StoredValues::encode(Precision::float32, 3, false, 1, {1.0f, 2.0f, 3.0f}), 0, probe);
  if (lanes && std::getenv("CAUSTICBENCH_LPI_SCALAR_LOOKUP") == nullptr) {
    EXPECT_EQ(lane_cases, 6 * 3 * 3);
  }
  EXPECT_EQ(expect_lookup_equals_reference(GridLayout(Vec3(0.1f, 0.0f, -0.1f), 0.9f, 1), "grid 1"), 0);
}

// The lanes' gathers and decoding against StoredDecoding::value, bit for bit: every float16 pattern
// but the signalling NaNs (subnormals, zeros of both signs, infinities and quiet NaNs among them;
// F16C quiets a signalling NaN, and float_to_half never stores one), every uint8 level signed and
// unsigned, float32 bits, for both channel counts, over point counts that leave a partial group of
// eight and end the stored values on the last point (the 4-byte gathers' clamp at the end).
TEST(LpiFastPaths, LaneDecodingEqualsStoredValuesDecode) {
  std::vector<float> probe;
  if (!decode_in_lanes(StoredValues::encode(Precision::float32, 3, false, 1, {1.0f, 2.0f, 3.0f}), 0, probe))
    GTEST_SKIP() << "no AVX2 and F16C: the lanes are not used";
  std::mt19937 random(17);
  for (int channels : {3, 9}) {
    for (size_t points : {size_t{1}, size_t{13}, size_t{2731}}) {
      const size_t samples = 3, values = samples * points * static_cast<size_t>(channels);
      struct Case {
        Precision precision;
        bool signed_channels;
      };
      for (const Case& kind : {Case{Precision::float16, false}, Case{Precision::uint8, false}, Case{Precision::uint8, true},
                               Case{Precision::float32, false}}) {
        std::vector<uint8_t> bytes(values * precision_bytes(kind.precision));
        for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(random());
        if (kind.precision == Precision::float16) {
          // Every half pattern, in order, as far as the values go (2731 points x 9 x 3 > 65536).
          for (size_t i = 0; i < values; ++i) {
            uint16_t half = static_cast<uint16_t>(i);
            if ((half & 0x7c00u) == 0x7c00u && (half & 0x3ffu) != 0) half |= 0x200u;  // a quiet NaN
            std::memcpy(bytes.data() + 2 * i, &half, sizeof(half));
          }
        }
        const std::vector<float> scales = {0.5f, 1.0f / 127.0f, 3.0f};
        const StoredValues stored = StoredValues::from_raw(kind.precision, channels, kind.signed_channels, points,
                                                           bytes, scales);
        for (size_t sample = 0; sample < samples; ++sample) {
          std::vector<float> lanes;
          ASSERT_TRUE(decode_in_lanes(stored, sample, lanes));
          // Decoding's value() (what the scalar lookup multiplies by its factor), not decode()'s scaled floats.
          std::vector<float> expected(points * static_cast<size_t>(channels));
          with_decoding(stored, [&](auto decoding) {
            using Decoding = decltype(decoding);
            const SampleBlock block = stored.block(sample);
            for (size_t point = 0; point < points; ++point)
              for (int c = 0; c < channels; ++c)
                expected[point * channels + c] = Decoding::value(Decoding::at(block, point, channels), c);
          });
          ASSERT_EQ(lanes.size(), expected.size());
          EXPECT_EQ(std::memcmp(lanes.data(), expected.data(), expected.size() * sizeof(float)), 0)
              << precision_name(kind.precision) << (kind.signed_channels ? " signed" : "") << ", " << channels
              << " channels, " << points << " points, light sample " << sample;
        }
      }
    }
  }
}

TEST(LpiFastPaths, ShellAndMultiresLookupsEqualReadingEachSampleAlone) {
  expect_lookup_equals_reference(ShellLayout(Vec3(0.0f), 1.0f, 3, 1, ShellSpacing::uniform), "shells");
  MultiresLayout tree(Vec3(0.0f), 1.0f, 3, 0.3);
  // A smooth field with a bump: the tree keeps fine cells in part of the cube only.
  std::vector<float> finest(tree.deposit_points() * 3);
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c) {
          const Vec3 p = tree.finest().cell_center(x, y, z);
          finest[tree.finest().index(x, y, z) * 3 + c] = std::exp(-8.0f * glm::dot(p - Vec3(0.5f), p - Vec3(0.5f)));
        }
  tree.adapt(finest, 3);
  ASSERT_GT(tree.points(), 8u);
  ASSERT_LT(tree.points(), 512u);
  expect_lookup_equals_reference(tree, "multires");
}

// The lookup rate of issue 11 (target: 30 million receiver points a second, barycentric, grid) on the
// ring under its turning sun, frame 1, 360 x 360, 42 light samples of 100,000 photons, every storage
// and blend. Prints per frame the best wall time of 20 renders and the CPU time per render (the
// machine is shared: CPU time is what the code costs), at 1 and 2 threads. Builds are kept in
// /tmp/lpi_lookup_throughput_builds between runs. LPI_STORAGES=grid,shells,multires,sh and
// LPI_PRECISIONS=float32,float16,uint8 choose what is measured (default: every storage, float32),
// LPI_RENDERS the renders timed (20). CAUSTICBENCH_LPI_SCALAR_LOOKUP=1 measures the grid's scalar
// lookup (the code before the lanes) in the same binary.
// Run: build/tests/test_lpi_fast_paths --gtest_also_run_disabled_tests --gtest_filter='*LookupThroughput*'
TEST(LpiFastPaths, DISABLED_LookupThroughputOnTheTurningRing) {
  // One thread: that thread's CPU time (the lookup alone); two: the process's (TBB's workers spin a
  // little after each loop, which counts).
  auto cpu_seconds = [](int threads) {
    timespec now;
    clock_gettime(threads == 1 ? CLOCK_THREAD_CPUTIME_ID : CLOCK_PROCESS_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
  };
  auto wall_seconds = [] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  };
  Scene scene = load_scene(std::string(CAUSTICBENCH_SCENES) + "/ring_turning_sun.yaml");
  set_resolution(scene, 360, 360);
  const int frame_index = 1;
  const PosedFrame frame(scene, frame_index);
  auto list = [](const char* variable, std::vector<std::string> otherwise) {
    const char* text = std::getenv(variable);
    if (!text) return otherwise;
    std::vector<std::string> items;
    const std::string all = text;
    for (size_t start = 0; start < all.size();) {
      const size_t comma = std::min(all.find(',', start), all.size());
      items.push_back(all.substr(start, comma - start));
      start = comma + 1;
    }
    return items;
  };
  const std::vector<std::string> storages = list("LPI_STORAGES", {"grid", "shells", "multires", "sh"});
  const std::vector<std::string> precisions = list("LPI_PRECISIONS", {"float32"});
  std::printf("%-8s %-8s %-11s %7s %9s %9s %10s %10s %10s\n", "storage", "values", "blend", "threads", "reads/pt",
              "best ms", "CPU ms", "M pts/s", "M pts/CPUs");
  for (const std::string& storage : storages) {
    for (const std::string& precision : precisions) {
      std::unique_ptr<CausticMethod> method;
      // storage: sh reads one coefficient stencil a light (blend and light_samples are not its knobs).
      const std::vector<std::string> blends =
          storage == "sh" ? std::vector<std::string>{"-"} : std::vector<std::string>{"nearest", "barycentric", "aligned"};
      for (const std::string& blend : blends) {
        RenderRequest request;
        request.scene = &scene;
        request.method = "lpi";
        request.frame = frame_index;
        std::vector<std::string> knobs = {"storage=" + storage, "precision=" + precision, "light_subdivision=1",
                                          "photons_per_sample=100000", "orientation=paper"};
        // sh always projects every geodesic vertex; the sampled storages are told to keep all 42.
        if (blend != "-") knobs.insert(knobs.end(), {"light_samples=all", "blend=" + blend});
        for (const std::string& knob : knobs) request.params.set_assignment(knob, "benchmark");
        const CheckedRequest checked = check_request(request);
        const PhaseKnobs phases = split_phases(checked.params, checked.method->info().params);
        if (!method) {
          method = checked.method->create();
          std::unique_ptr<RestPose> rest;
          BuildCacheFolder builds("/tmp/lpi_lookup_throughput_builds");
          prepare_method(*method, prepare_context(scene, {frame_index}, nullptr, rest), phases.build, &builds);
        }
        method->update(frame.context(), phases.frame);
        const double receivers = static_cast<double>(frame.gbuffer.receiver_count());
        for (int threads : {1, 2}) {
          const ThreadLimit limit(threads);
          method->render(frame.gbuffer, phases.render);  // warm
          const int renders = std::getenv("LPI_RENDERS") ? std::atoi(std::getenv("LPI_RENDERS")) : 20;
          double best = 1e30;
          const double cpu_start = cpu_seconds(threads);
          for (int i = 0; i < renders; ++i) {
            const double start = wall_seconds();
            method->render(frame.gbuffer, phases.render);
            best = std::min(best, wall_seconds() - start);
          }
          const double cpu = (cpu_seconds(threads) - cpu_start) / renders;
          double reads = 0.0;
          for (const auto& [name, value] : method->counters())
            if (name == "volume_reads_per_frame") reads = value;
          std::printf("%-8s %-8s %-11s %7d %9.2f %9.2f %10.2f %10.2f %10.2f\n", storage.c_str(), precision.c_str(),
                      blend.c_str(), threads, reads / receivers, best * 1e3, cpu * 1e3, receivers / best * 1e-6,
                      receivers / cpu * 1e-6);
        }
      }
    }
  }
}
