// lpi's `multires_tree: per_sample` (methods/lpi/multires_layout.h): an octree per light sample, each
// refined only where its own caustic varies. Against what it must equal: the shared tree built from
// that light sample alone, the finest grid within error_threshold, its memory formula, and a
// brute-force evaluation that finds each finest cell's leaf without any tree.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "methods/lpi/lookup.h"
#include "methods/lpi/multires_layout.h"
#include "methods/lpi/precompute.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using namespace causticbench::lpi;

namespace {

constexpr int kDepth = 4;  // 16^3 finest cells
constexpr size_t kSamples = 4;

// Light sample s, channel c at p: sample 0 is flat, the others a peak each (at its own place, of its
// own height) on a gentle slope, so each sample's tree must refine somewhere else. Vector channels
// (9) take signs.
float field(size_t s, int c, const Vec3& p, int channels) {
  if (s == 0) return 0.4f + 0.1f * static_cast<float>(c % 3);
  const Vec3 peaks[] = {Vec3(0.5f, -0.4f, 0.3f), Vec3(-0.5f, 0.5f, -0.2f), Vec3(0.1f, 0.1f, -0.6f)};
  const Vec3 d = p - peaks[(s - 1) % 3];
  const float value = static_cast<float>(s) * (0.2f + 2.0f * std::exp(-30.0f * glm::dot(d, d)) + 0.05f * p.x) *
                      (1.0f + 0.1f * static_cast<float>(c % 3));
  return channels == 9 && c % 3 == 1 ? -value : value;
}

std::vector<float> finest_values(const GridLayout& grid, size_t samples, int channels) {
  std::vector<float> values(samples * grid.points() * channels);
  const int n = grid.resolution();
  for (size_t s = 0; s < samples; ++s)
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          for (int c = 0; c < channels; ++c)
            values[(s * grid.points() + grid.index(x, y, z)) * channels + c] = field(s, c, grid.cell_center(x, y, z), channels);
  return values;
}

// First value of each light sample's block in the per-sample trees' values.
std::vector<size_t> block_starts(const std::vector<size_t>& block_points, int channels) {
  std::vector<size_t> starts{0};
  for (size_t points : block_points) starts.push_back(starts.back() + points * channels);
  return starts;
}

// Brute force, without a tree: the value finest cell (x, y, z) of light sample s reads. Going down
// from the whole cube, the first aligned block around the cell whose every finest value lies within
// `threshold` x the sample's largest magnitude of its mean is the cell's leaf (the descent stops
// there); the value is that mean. Level by level, coarsest first, each block's test made once.
std::vector<float> leaf_values_by_brute_force(const GridLayout& grid, const std::vector<float>& finest, size_t s,
                                              int channels, double threshold) {
  const int n = grid.resolution();
  const size_t block = grid.points() * channels;
  const float* values = finest.data() + s * block;
  double largest = 0.0;
  for (size_t i = 0; i < block; ++i) largest = std::max(largest, static_cast<double>(std::fabs(values[i])));
  std::vector<float> result(block);
  std::vector<bool> assigned(grid.points(), false);
  for (int size = n; size >= 1; size /= 2)
    for (int z0 = 0; z0 < n; z0 += size)
      for (int y0 = 0; y0 < n; y0 += size)
        for (int x0 = 0; x0 < n; x0 += size) {
          if (assigned[grid.index(x0, y0, z0)]) continue;  // inside a coarser leaf
          bool within = true;
          std::vector<double> means(channels, 0.0);
          for (int c = 0; c < channels; ++c) {
            for (int k = z0; k < z0 + size; ++k)
              for (int j = y0; j < y0 + size; ++j)
                for (int i = x0; i < x0 + size; ++i) means[c] += values[grid.index(i, j, k) * channels + c];
            means[c] /= static_cast<double>(size) * size * size;
            for (int k = z0; k < z0 + size; ++k)
              for (int j = y0; j < y0 + size; ++j)
                for (int i = x0; i < x0 + size; ++i)
                  within = within && std::fabs(values[grid.index(i, j, k) * channels + c] - means[c]) <= threshold * largest;
          }
          if (!within && size > 1) continue;
          for (int k = z0; k < z0 + size; ++k)
            for (int j = y0; j < y0 + size; ++j)
              for (int i = x0; i < x0 + size; ++i) {
                assigned[grid.index(i, j, k)] = true;
                for (int c = 0; c < channels; ++c) result[grid.index(i, j, k) * channels + c] = static_cast<float>(means[c]);
              }
        }
  return result;
}

}  // namespace

// The flat light sample is one leaf, one node; the peaked ones refine, each its own tree, and each
// tree is exactly the shared tree built from that light sample alone. The shared tree over all of
// them keeps the union of their refinements in every sample's block.
TEST(LpiMultiresPerSample, EachSampleRefinesOnlyWhereItsOwnCausticVaries) {
  MultiresLayout trees(Vec3(0.0f), 1.0f, kDepth, 0.03, MultiresTree::per_sample);
  const std::vector<float> finest = finest_values(trees.finest(), kSamples, 3);
  const std::vector<float> values = trees.adapt(finest, 3);
  const std::vector<size_t> leaves = trees.block_points(kSamples);
  ASSERT_EQ(trees.sample_trees(), kSamples);
  EXPECT_EQ(leaves[0], 1u);
  EXPECT_EQ(trees.sample_nodes(0), 1u);
  size_t total = 0, node_words = 0;
  for (size_t s = 0; s < kSamples; ++s) {
    total += leaves[s];
    node_words += trees.sample_nodes(s);
  }
  EXPECT_EQ(trees.points(), total);
  EXPECT_EQ(trees.nodes(), node_words);
  EXPECT_EQ(values.size(), total * 3);
  const std::vector<uint32_t> structure = trees.structure();
  for (size_t s = 1; s < kSamples; ++s) {
    EXPECT_GT(leaves[s], 64u) << "sample " << s << " should refine around its peak";
    MultiresLayout alone(Vec3(0.0f), 1.0f, kDepth, 0.03);
    const std::vector<float> own(finest.begin() + s * finest.size() / kSamples,
                                 finest.begin() + (s + 1) * finest.size() / kSamples);
    const std::vector<float> own_values = alone.adapt(own, 3);
    ASSERT_EQ(alone.points(), leaves[s]) << "sample " << s;
    // Its node words, child indices made relative to its root (structure: count, roots, nodes).
    const uint32_t root = structure[1 + s];
    for (size_t i = 0; i < alone.nodes(); ++i) {
      const uint32_t word = structure[1 + kSamples + root + i];
      EXPECT_EQ((word & 0x80000000u) ? word : word - root, alone.structure()[i]) << "sample " << s << ", node " << i;
    }
    const size_t start = block_starts(leaves, 3)[s];
    EXPECT_TRUE(std::equal(own_values.begin(), own_values.end(), values.begin() + start)) << "sample " << s;
  }
  MultiresLayout shared(Vec3(0.0f), 1.0f, kDepth, 0.03);
  shared.adapt(finest, 3);
  std::printf("per-sample leaves %zu / %zu / %zu / %zu; shared tree %zu leaves in each of the %zu blocks\n", leaves[0],
              leaves[1], leaves[2], leaves[3], shared.points(), kSamples);
  for (size_t s = 0; s < kSamples; ++s) EXPECT_LT(leaves[s], shared.points()) << "sample " << s;
  // Saved and restored, the trees read the same leaves.
  MultiresLayout restored(Vec3(0.0f), 1.0f, kDepth, 0.03, MultiresTree::per_sample);
  restored.restore(structure);
  EXPECT_EQ(restored.block_points(kSamples), leaves);
  for (size_t s = 0; s < kSamples; ++s)
    for (int cell = 0; cell < 4096; cell += 37)
      EXPECT_EQ(restored.leaf_of(cell % 16, cell / 16 % 16, cell / 256, s), trees.leaf_of(cell % 16, cell / 16 % 16, cell / 256, s));
}

// Read through its own tree, each light sample lies within error_threshold x its own largest value
// of the finest grid's lookup (samples 1 to 3 differ in scale: the bound is each one's).
TEST(LpiMultiresPerSample, ReadsBackWithinEachSamplesThreshold) {
  const double threshold = 0.05;
  MultiresLayout trees(Vec3(0.0f), 1.0f, kDepth, threshold, MultiresTree::per_sample);
  const std::vector<float> finest = finest_values(trees.finest(), kSamples, 3);
  const std::vector<float> values = trees.adapt(finest, 3);
  const std::vector<size_t> starts = block_starts(trees.block_points(kSamples), 3);
  const size_t finest_block = trees.deposit_points() * 3;
  std::mt19937 random(5);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  for (size_t s = 0; s < kSamples; ++s) {
    float largest = 0.0f;
    for (size_t i = 0; i < finest_block; ++i) largest = std::max(largest, std::fabs(finest[s * finest_block + i]));
    double worst = 0.0;
    for (int i = 0; i < 3000; ++i) {
      const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
      const Stencil cells = trees.finest_stencil(p);
      Stencil leaves = cells;
      trees.to_leaves(leaves, s);
      for (int c = 0; c < 3; ++c) {
        double tree = 0.0, grid = 0.0;
        for (int k = 0; k < cells.count; ++k) {
          tree += cells.weights[k] * values[starts[s] + leaves.points[k] * 3 + c];
          grid += cells.weights[k] * finest[s * finest_block + cells.points[k] * 3 + c];
        }
        worst = std::max(worst, std::fabs(tree - grid));
      }
    }
    std::printf("sample %zu: worst difference %.4g, bound %.4g\n", s, worst, threshold * largest);
    EXPECT_LE(worst, threshold * largest * (1.0 + 1e-5)) << "sample " << s;
    if (s > 0) {
      EXPECT_GT(worst, 0.1 * threshold * largest) << "sample " << s << ": it should have approximated";
    }
  }
}

// Bytes per light sample: each sample's leaves at its precision, its node words and its root word;
// the mean over the light samples is what the run reports. The flat sample costs 3 + 4 + 4 bytes.
TEST(LpiMultiresPerSample, MemoryIsLeavesPlusEachTreesWords) {
  auto trees = std::make_unique<MultiresLayout>(Vec3(0.0f), 1.0f, kDepth, 0.03, MultiresTree::per_sample);
  const std::vector<float> values = trees->adapt(finest_values(trees->finest(), kSamples, 3), 3);
  const std::vector<size_t> leaves = trees->block_points(kSamples);
  ObjectVolumes volumes;
  volumes.samples.directions.assign(kSamples, Vec3(0.0f, 1.0f, 0.0f));
  volumes.values = StoredValues::encode(Precision::uint8, 3, false, leaves, values);
  double expected = 0.0;
  for (size_t s = 0; s < kSamples; ++s) {
    EXPECT_EQ(volumes.values.block_points(s), leaves[s]);
    expected += 3.0 * static_cast<double>(leaves[s]) + 4.0 * static_cast<double>(trees->sample_nodes(s)) + 4.0;
  }
  EXPECT_EQ(3.0 * leaves[0] + 4.0 * trees->sample_nodes(0) + 4.0, 11.0);
  EXPECT_EQ(trees->index_bytes(), 4 * (trees->nodes() + kSamples));
  EXPECT_EQ(volumes.values.memory_bytes(), 3 * trees->points() + 4 * kSamples);  // values and uint8 steps
  volumes.layout = std::move(trees);
  EXPECT_DOUBLE_EQ(bytes_per_light_sample(volumes), expected / kSamples);
}

// The whole lookup (lookup.h, every blend's shape of reads, rotated ones included, both orientations,
// float32 and uint8) through the per-sample trees, against the same receivers read on the finest
// grid whose cells hold the brute-force leaf values: equal to rounding.
TEST(LpiMultiresPerSample, LookupsAgreeWithBruteForce) {
  const double threshold = 0.04;
  GBuffer gbuffer;
  gbuffer.width = 31;
  gbuffer.height = 29;
  std::mt19937 random(9);
  std::uniform_real_distribution<float> coordinate(-0.95f, 0.95f);
  std::normal_distribution<float> gaussian;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    gbuffer.position.emplace_back(coordinate(random), coordinate(random), coordinate(random));
    gbuffer.normal.push_back(glm::normalize(Vec3(gaussian(random), gaussian(random), gaussian(random))));
    gbuffer.receiver.push_back(pixel % 7 == 3 ? 0 : 1);
  }
  BuildSpaceMap map;
  map.normals = rotation_between(glm::normalize(Vec3(0.3f, 1.0f, 0.2f)), Vec3(0.0f, 1.0f, 0.0f));
  map.linear = map.normals;
  const glm::mat3 turn = rotation_between(glm::normalize(Vec3(0.2f, 1.0f, 0.1f)), Vec3(0.0f, 1.0f, 0.0f));
  auto light = [](std::vector<SampleRead> reads) {
    LightView view;
    view.irradiance = Color(1.0f, 0.8f, 0.5f);
    view.reads.count = static_cast<int>(reads.size());
    for (size_t r = 0; r < reads.size(); ++r) view.reads.reads[r] = reads[r];
    return view;
  };
  const std::vector<std::vector<LightView>> cases = {
      {light({{1, 1.0f, false, glm::mat3(1.0f)}})},
      {light({{0, 0.2f, false, glm::mat3(1.0f)}, {2, 0.5f, false, glm::mat3(1.0f)}, {3, 0.3f, false, glm::mat3(1.0f)}})},
      {light({{3, 0.25f, false, glm::mat3(1.0f)}, {1, 0.5f, true, turn}, {2, 0.25f, true, glm::transpose(turn)}})},
  };
  for (int channels : {3, 9}) {
    MultiresLayout trees(Vec3(0.0f), 1.0f, kDepth, threshold, MultiresTree::per_sample);
    const std::vector<float> finest = finest_values(trees.finest(), kSamples, channels);
    const std::vector<float> values = trees.adapt(finest, channels);
    std::vector<float> expanded;
    for (size_t s = 0; s < kSamples; ++s) {
      const std::vector<float> sample = leaf_values_by_brute_force(trees.finest(), finest, s, channels, threshold);
      expanded.insert(expanded.end(), sample.begin(), sample.end());
    }
    for (Precision precision : {Precision::float32, Precision::uint8}) {
      const bool signed_channels = channels == 9;
      const StoredValues tree_values =
          StoredValues::encode(precision, channels, signed_channels, trees.block_points(kSamples), values);
      const StoredValues grid_values =
          StoredValues::encode(precision, channels, signed_channels, trees.deposit_points(), expanded);
      for (size_t c = 0; c < cases.size(); ++c) {
        Image tree_image(gbuffer.width, gbuffer.height, 3, 0.0f), grid_image(gbuffer.width, gbuffer.height, 3, 0.0f);
        add_object_caustic(trees, ObjectView{tree_values, map, cases[c].data(), cases[c].size(), Outside::clamp}, gbuffer,
                           0, gbuffer.pixel_count(), tree_image);
        add_object_caustic(trees.finest(), ObjectView{grid_values, map, cases[c].data(), cases[c].size(), Outside::clamp},
                           gbuffer, 0, gbuffer.pixel_count(), grid_image);
        double worst = 0.0, largest = 0.0;
        for (size_t i = 0; i < tree_image.values().size(); ++i) {
          worst = std::max(worst, static_cast<double>(std::fabs(tree_image.values()[i] - grid_image.values()[i])));
          largest = std::max(largest, static_cast<double>(grid_image.values()[i]));
        }
        EXPECT_GT(largest, 0.1) << "case " << c;
        EXPECT_LE(worst, 1e-5 * largest) << channels << " channels, " << precision_name(precision) << ", case " << c;
      }
    }
  }
}

// With an environment light the light samples' volumes are summed into one, which per-sample trees
// cannot give: refused before any photon is shot, naming the knob.
TEST(LpiMultiresPerSample, EnvironmentLightsAreRefused) {
  const Scene scene = causticbench::testing::scene_from_yaml(causticbench::testing::replace_once(
      causticbench::testing::kSmallGlassSphere, "{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}",
      "{name: sky, type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, "
      "solid_angle_sr: 0.1}"));
  const std::string message = causticbench::testing::input_error_message([&] {
    causticbench::testing::render(scene, "lpi", {"storage=multires", "multires_tree=per_sample", "photons_per_sample=100"});
  });
  EXPECT_NE(message.find("light 'sky' is an environment light"), std::string::npos) << message;
  EXPECT_NE(message.find("multires_tree: per_sample"), std::string::npos) << message;
}

// One light sample (a static sun): its own tree is the shared tree, so the image is the same bit for
// bit and the memory one root word more. The knob at shared keeps the run and build keys of runs
// from before it; per_sample names its own.
TEST(LpiMultiresPerSample, OneLightSampleIsTheSharedTreeAndKeysDiffer) {
  const Scene scene = causticbench::testing::scene_from_yaml(causticbench::testing::kSmallGlassSphere);
  const std::vector<std::string> common = {"storage=multires", "multires_depth=4", "error_threshold=0.05",
                                           "photons_per_sample=3000", "precision=uint8"};
  auto with = [&](const std::string& tree) {
    std::vector<std::string> knobs = common;
    knobs.push_back("multires_tree=" + tree);
    return causticbench::testing::render(scene, "lpi", knobs);
  };
  const FrameResult shared = with("shared"), per_sample = with("per_sample");
  EXPECT_EQ(shared.caustic.values(), per_sample.caustic.values());
  const nlohmann::json& one = shared.method_record["objects"][0];
  const nlohmann::json& own = per_sample.method_record["objects"][0];
  EXPECT_EQ(one["light_samples"], 1);
  EXPECT_EQ(own["sample_points"], one["sample_points"]);
  EXPECT_DOUBLE_EQ(own["bytes_per_light_sample"].get<double>(), one["bytes_per_light_sample"].get<double>() + 4.0);
  const MethodInfo& info = find_method("lpi").info();
  auto key = [&](const std::vector<std::string>& knobs) {
    ParamDict dict;
    for (const std::string& knob : knobs) dict.set_assignment(knob, "test");
    return dict.resolve(info.params, "lpi").key_json(info.params);
  };
  EXPECT_EQ(key({"storage=multires"}), key({"storage=multires", "multires_tree=shared"}));
  EXPECT_NE(key({"storage=multires"}), key({"storage=multires", "multires_tree=per_sample"}));
}
