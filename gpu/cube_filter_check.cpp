#include "gpu/cube_filter_check.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <random>
#include <utility>
#include <vector>

namespace causticbench::gpu {

namespace {

const uint32_t kProbeSpirv[] =
#include "cube_filter_probe.spv.inc"
    ;

constexpr int kSize = 64;
constexpr uint32_t kQueries = 8192;

// Mean |L - 1| of lookups at random directions with round footprints of `radius` (in direction units).
double mean_deviation(Context& context, const CubeTexture& texture, ComputePipeline& pipeline, float radius) {
  std::mt19937 random(17);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<float> queries(12ull * kQueries, 0.0f);
  for (uint32_t i = 0; i < kQueries; ++i) {
    float d[3], t[3], length;
    do {
      for (float& x : d) x = uniform(random);
      length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    } while (length < 0.1f || length > 1.0f);
    for (float& x : d) x /= length;
    // A tangent: any vector minus its component along d.
    do {
      for (float& x : t) x = uniform(random);
      float along = t[0] * d[0] + t[1] * d[1] + t[2] * d[2];
      for (int k = 0; k < 3; ++k) t[k] -= along * d[k];
      length = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    } while (length < 0.1f);
    for (float& x : t) x /= length;
    float b[3] = {d[1] * t[2] - d[2] * t[1], d[2] * t[0] - d[0] * t[2], d[0] * t[1] - d[1] * t[0]};
    for (int k = 0; k < 3; ++k) {
      queries[12 * i + k] = d[k];
      queries[12 * i + 4 + k] = radius * t[k];
      queries[12 * i + 8 + k] = radius * b[k];
    }
  }
  Buffer query_buffer(context, queries.size() * sizeof(float)), result_buffer(context, 4ull * kQueries * sizeof(float));
  query_buffer.upload(queries.data(), queries.size() * sizeof(float));
  uint32_t count = kQueries;
  pipeline.dispatch({&query_buffer, &result_buffer}, &count, (kQueries + 63) / 64, {&texture});
  std::vector<float> results(4ull * kQueries);
  result_buffer.download(results.data(), results.size() * sizeof(float));
  double sum = 0.0;
  for (uint32_t i = 0; i < kQueries; ++i) sum += std::fabs(results[4 * i] - 1.0);
  return sum / kQueries;
}

}  // namespace

std::string CubeFilterCheck::summary() const {
  char text[256];
  std::snprintf(text, sizeof text, "%s cube filtering %s explicit gradients (checkerboard deviation %.3f at 1e-5, %.3f at 0.3)",
                anisotropic ? "anisotropic" : "isotropic", honours_gradients ? "honours" : "ignores",
                deviation_small_footprint, deviation_large_footprint);
  return text;
}

CubeFilterCheck check_cube_filtering(Context& context, bool anisotropic) {
  std::vector<std::vector<float>> levels;
  for (int extent = kSize, level = 0; extent >= 1; extent /= 2, ++level) {
    std::vector<float> texels(6ull * extent * extent * 4, 1.0f);
    if (level == 0) {
      for (int face = 0; face < 6; ++face) {
        for (int y = 0; y < extent; ++y) {
          for (int x = 0; x < extent; ++x) texels[((static_cast<size_t>(face) * extent + y) * extent + x) * 4] = (x + y) % 2 ? 2.0f : 0.0f;
        }
      }
    }
    levels.push_back(std::move(texels));
  }
  CubeTexture texture(context, kSize, levels, anisotropic);
  ComputePipeline pipeline(context, kProbeSpirv, sizeof kProbeSpirv, 2, sizeof(uint32_t), 1);
  CubeFilterCheck check;
  check.anisotropic = anisotropic;
  check.deviation_small_footprint = mean_deviation(context, texture, pipeline, 1e-5f);
  check.deviation_large_footprint = mean_deviation(context, texture, pipeline, 0.3f);
  check.honours_gradients = check.deviation_small_footprint > 0.15 && check.deviation_large_footprint < 0.02;
  return check;
}

CubeFilterCheck cached_cube_filter_check(Context& context, bool anisotropic) {
  static std::mutex mutex;
  static std::map<std::pair<std::string, bool>, CubeFilterCheck> checks;
  std::lock_guard<std::mutex> lock(mutex);
  auto key = std::make_pair(context.device_name(), anisotropic);
  auto found = checks.find(key);
  if (found == checks.end()) found = checks.emplace(key, check_cube_filtering(context, anisotropic)).first;
  return found->second;
}

}  // namespace causticbench::gpu
