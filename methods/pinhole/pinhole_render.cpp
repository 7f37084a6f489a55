// pinhole's per-pixel work (render): every receiver point gathers the light of every reflector sample
// through its pinhole, on the CPU or through the Vulkan kernel.
#include "methods/pinhole/pinhole.h"

#include <fmt/format.h>

#include "core/optics.h"
#include "core/parallel.h"
#include "gpu/cube_filter_check.h"
#include "methods/common/gpu_arrays.h"
#include "methods/pinhole/cube_filter.h"
#include "methods/pinhole/reflection_lanes.h"
#include "methods/pinhole/texel_fetch.h"
#include "methods/pinhole/throughput.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

namespace {

// Direction towards the light seen through a sample (normal n) from a receiver in `direction` (unit,
// receiver to sample), and the cosine at the sample. Returns false when no light can pass (back
// face, total internal reflection).
inline bool light_direction(const Vec3& direction, const Vec3& normal_in, bool two_sided, float ior,
                            bool refraction, Vec3& to_light, float& cos_sample) {
  Vec3 normal = normal_in;
  // Reflection: the receiver faces the reflecting side. Refraction: the receiver is inside the
  // medium (behind the outward normal) and the ray leaves through the sample towards the light.
  cos_sample = refraction ? glm::dot(normal, direction) : -glm::dot(normal, direction);
  if (cos_sample <= 0.0f) {
    if (!two_sided) return false;
    normal = -normal;
    cos_sample = -cos_sample;
  }
  if (!refraction) {
    to_light = reflect(direction, normal);
    return true;
  }
  return refract(direction, -normal, 1.0f / ior, to_light);
}

}  // namespace

Image PinholeMethod::render(const GBuffer& gbuffer, const ParamSet& params) {
  Image result(gbuffer.width, gbuffer.height, 3);
  const std::vector<ReflectorSample>& samples = samples_.samples;
  if (samples.empty()) return result;
  evaluations_ = static_cast<double>(gbuffer.receiver_count()) * static_cast<double>(samples.size());
  if (vulkan_) {
    fill_receivers(gbuffer, params, frame_data_);
    return image_of_rgba(gbuffer.width, gbuffer.height, vulkan_->render(frame_data_, gpu_render_ms_));
  }
  const float epsilon = epsilon_of(params);
  const bool attenuation = params.boolean("attenuation");
  const bool fresnel = params.boolean("fresnel");
  // Per sample: interaction auto refracts at glass and reflects elsewhere (pinhole_refracts).
  std::vector<uint8_t> refracts(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) refracts[i] = pinhole_refracts(interaction_, *sample_materials_[i]);
  const std::string& filtering = build_.text("filtering");
  const bool filtered = filtering != "none" && (filtered_map_ || cube_filter_);
  // The skip of footprints that reach no light changes nothing (methods/pinhole/tests/test_pinhole.cpp); the variable
  // turns it off to show that.
  const bool skip = std::getenv("CAUSTICBENCH_PINHOLE_NO_SKIP") == nullptr;
  const bool anisotropic = filtering == "anisotropic";
  const float footprint_radius = this->footprint_radius();
  // Structure of arrays for the hot loop (pixels x samples): positions and normals contiguous.
  const size_t count = samples.size();
  // Padded to a multiple of 8 for the vector kernel; padding samples have a zero normal, so they never face.
  const size_t padded = (count + 7) / 8 * 8;
  std::vector<float> px(padded, 0.0f), py(padded, 0.0f), pz(padded, 1e6f), nx(padded, 0.0f), ny(padded, 0.0f),
      nz(padded, 0.0f);
  for (size_t i = 0; i < count; ++i) {
    px[i] = samples[i].position.x;
    py[i] = samples[i].position.y;
    pz[i] = samples[i].position.z;
    nx[i] = samples[i].normal.x;
    ny[i] = samples[i].normal.y;
    nz[i] = samples[i].normal.z;
  }
  std::vector<float> two_sided(padded, 0.0f);
  for (size_t i = 0; i < count; ++i) two_sided[i] = samples[i].two_sided ? 1.0f : 0.0f;
  const float sample_area = samples.front().area;
  if (!filtered && !any_refracts_) {
    // The common case (Fig. 4 to 7): geometry in vectorised blocks, then a lookup per facing sample,
    // with the throughput from a table per material (methods/pinhole/throughput.h).
    std::vector<ThroughputTable> tables;
    std::vector<uint16_t> table_of(count);
    for (size_t i = 0; i < count; ++i) {
      auto found = std::find_if(tables.begin(), tables.end(),
                                [&](const ThroughputTable& t) { return t.material() == sample_materials_[i]; });
      if (found == tables.end()) found = tables.insert(tables.end(), ThroughputTable(*sample_materials_[i], fresnel));
      table_of[i] = static_cast<uint16_t>(found - tables.begin());
    }
    table_error_ = 0.0f;
    for (const ThroughputTable& table : tables) table_error_ = std::max(table_error_, table.max_error());
    // The same for the vector fetch (texel_fetch.h): the tables' values flat, the table index as int32.
    std::vector<float> throughput_values;
    for (const ThroughputTable& table : tables)
      for (const Color& value : table.values()) throughput_values.insert(throughput_values.end(), {value.r, value.g, value.b});
    std::vector<int32_t> table_index(table_of.begin(), table_of.end());
    table_index.resize(padded, 0);  // the vector fetch reads whole groups of 8
    const bool vector_fetch = vector_fetch_enabled();
    // A block of samples is taken through every pixel of a chunk before the next block: a sample's
    // texels move by about one texel from one pixel to the next, so the block's texels stay cached. Each
    // pixel's sum still adds the blocks in order, so the output is the same bit for bit as pixel by
    // pixel.
    constexpr size_t kBlock = 256, kPixels = 64;
    parallel_blocks(gbuffer.pixel_count(), kPixels, [&](size_t begin, size_t end, size_t) {
      alignas(32) float texel_s[kBlock], texel_t[kBlock], weight[kBlock], cos_sample[kBlock];
      alignas(32) int face[kBlock], block[kBlock];
      const std::vector<uint8_t>& occupied = cube_map_.occupancy();
      uint16_t indices[kBlock];
      const float resolution = static_cast<float>(cube_map_.resolution());
      const uint32_t* packed = packed_map_.texels().empty() ? nullptr : packed_map_.texels().data();
      size_t pixels[kPixels];
      Color sums[kPixels];
      size_t receivers = 0;
      for (size_t pixel = begin; pixel < end; ++pixel) {
        if (gbuffer.receiver[pixel]) pixels[receivers++] = pixel;
      }
      std::fill(sums, sums + receivers, Color(0.0f));
      for (size_t first = 0; first < count; first += kBlock) {
        size_t n = std::min(kBlock, count - first);
        for (size_t r = 0; r < receivers; ++r) {
          const size_t pixel = pixels[r];
          Color& sum = sums[r];
          reflection_block(ReflectionBlock{(n + 7) / 8 * 8, &px[first], &py[first], &pz[first], &nx[first], &ny[first],
                                           &nz[first], &two_sided[first], gbuffer.position[pixel], gbuffer.normal[pixel],
                                           epsilon, sample_area, resolution,
                                           static_cast<float>(cube_map_.occupancy_blocks()), attenuation, face, block,
                                           texel_s, texel_t, weight, cos_sample});
          // Under an environment map (packed) every block is lit: the vector fetch compacts the facing
          // samples itself, by a permutation eight at a time.
          if (packed && vector_fetch) {
            fetch_sum_avx2(FetchBlock{face, texel_s, texel_t, weight, cos_sample, nullptr, (n + 7) / 8 * 8,
                                      cube_map_.texels().data(), packed, packed_map_.unit_bits(), cube_map_.resolution(),
                                      throughput_values.data(), table_index.data() + first, tables.size() == 1},
                           sum);
            continue;
          }
          // Compact the facing samples that look into a lit part of the map without a branch (about
          // half face away, at random, which a branch would mispredict), then look them up.
          size_t facing = 0;
          for (size_t j = 0; j < n; ++j) {
            indices[facing] = static_cast<uint16_t>(j);
            facing += (weight[j] > 0.0f) & (occupied[block[j]] != 0);
          }
          size_t k = 0;
          if (vector_fetch)
            k = fetch_sum_avx2(FetchBlock{face, texel_s, texel_t, weight, cos_sample, indices, facing,
                                          cube_map_.texels().data(), nullptr, 0, cube_map_.resolution(),
                                          throughput_values.data(), table_index.data() + first, false},
                               sum);
          for (; k < facing; ++k) {
            size_t j = indices[k];
            Color radiance = cube_map_.lookup_texel(face[j], texel_s[j], texel_t[j]);
            if (radiance.r + radiance.g + radiance.b <= 0.0f) continue;
            sum += radiance * tables[table_of[first + j]](cos_sample[j]) * weight[j];
          }
        }
      }
      for (size_t r = 0; r < receivers; ++r) result.set_rgb(pixels[r], sums[r]);
    });
    return result;
  }
  // Differential point samples: the points p + r u, p + r v and their normals n + r dn/du, n + r dn/dv
  // (normalised) depend on the sample only; made once here rather than for every pixel.
  std::vector<Vec3> moved_positions, moved_normals;
  if (filtered) {
    for (const ReflectorSample& sample : samples) {
      moved_positions.insert(moved_positions.end(), {sample.position + footprint_radius * sample.direction_u,
                                                     sample.position + footprint_radius * sample.direction_v});
      moved_normals.insert(moved_normals.end(), {glm::normalize(sample.normal + footprint_radius * sample.normal_derivative_u),
                                                 glm::normalize(sample.normal + footprint_radius * sample.normal_derivative_v)});
    }
  }
  // The vector pre-skip (filtered_skip_lanes) where the own filter looks up a compact light.
  const bool prefilter = cube_filter_ && skip && !any_refracts_ && !cube_filter_->lit_everywhere();
  std::vector<std::vector<float>> moved_arrays(12, std::vector<float>(padded, 0.0f));
  if (prefilter) {
    for (int k = 0; k < 2; ++k) std::fill(moved_arrays[3 * k + 2].begin(), moved_arrays[3 * k + 2].end(), 1e6f);
    for (size_t i = 0; i < count; ++i) {
      for (int k = 0; k < 2; ++k) {
        for (int c = 0; c < 3; ++c) {
          moved_arrays[3 * k + c][i] = moved_positions[2 * i + k][c];
          moved_arrays[6 + 3 * k + c][i] = moved_normals[2 * i + k][c];
        }
      }
    }
  }
  const std::vector<float> cone_data = prefilter ? cube_filter_->lit_cone_data() : std::vector<float>();
  parallel_blocks(gbuffer.pixel_count(), 64, [&](size_t begin, size_t end, size_t) {
    constexpr size_t kBlock = 256;
    alignas(32) float keep[kBlock];
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      const Vec3 x = gbuffer.position[pixel], receiver_normal = gbuffer.normal[pixel];
      Color sum(0.0f);
      auto evaluate = [&](size_t i) {
        Vec3 offset(px[i] - x.x, py[i] - x.y, pz[i] - x.z);
        float distance2 = glm::dot(offset, offset);
        float cos_receiver_scaled = glm::dot(receiver_normal, offset);
        if (cos_receiver_scaled <= 0.0f) return;  // back-face culling at the receiver, before any root
        const ReflectorSample& sample = samples[i];
        Vec3 direction = offset * (1.0f / std::sqrt(distance2));
        float cos_receiver = glm::dot(receiver_normal, direction);
        const Material& material = *sample_materials_[i];
        const Interaction interaction{refracts[i] != 0, fresnel};
        Vec3 to_light;
        float cos_sample;
        if (!light_direction(direction, Vec3(nx[i], ny[i], nz[i]), sample.two_sided, material.ior, interaction.refract,
                             to_light, cos_sample)) {
          return;
        }
        Color radiance;
        if (filtered) {
          // Differential point sample: reflection (or refraction) directions at p + r u and p + r v
          // with the normals n + r dn/du and n + r dn/dv give the footprint's two gradients.
          Vec3 gradients[2];
          for (int k = 0; k < 2; ++k) {
            Vec3 moved = moved_positions[2 * i + k] - x;
            const Vec3& moved_normal = moved_normals[2 * i + k];
            Vec3 moved_light;
            float unused_cos;
            gradients[k] = light_direction(glm::normalize(moved), moved_normal, sample.two_sided, material.ior,
                                           interaction.refract, moved_light, unused_cos)
                               ? moved_light - to_light
                               : Vec3(0.0f);
          }
          radiance = cube_filter_ ? cube_filter_->lookup(to_light, gradients[0], gradients[1], anisotropic, skip)
                                  : filtered_map_->lookup(to_light, gradients[0], gradients[1], anisotropic);
        } else {
          radiance = cube_map_.lookup(to_light);
        }
        if (radiance.r + radiance.g + radiance.b <= 0.0f) return;
        float geometry = attenuation ? cos_sample * cos_receiver / (distance2 + epsilon) : 1.0f;
        sum += radiance * light_throughput(material, interaction, cos_sample) * (geometry * sample.area);
      };
      if (!prefilter) {
        for (size_t i = 0; i < count; ++i) evaluate(i);
      } else {
        for (size_t first = 0; first < count; first += kBlock) {
          size_t n = std::min(kBlock, count - first);
          FilteredSkipBlock block{(n + 7) / 8 * 8, &px[first], &py[first], &pz[first], &nx[first], &ny[first], &nz[first],
                                  {}, x, cone_data.data(), cone_data.size() / 4, cube_filter_->support_per_texel(),
                                  0.5f * static_cast<float>(cube_filter_->level_size(0)), anisotropic, keep};
          for (int k = 0; k < 12; ++k) block.moved[k] = &moved_arrays[k][first];
          filtered_skip(block);
          for (size_t j = 0; j < n; ++j) {
            if (keep[j] != 0.0f) evaluate(first + j);
          }
        }
      }
      result.set_rgb(pixel, sum);
    }
  });
  return result;
}

float PinholeMethod::epsilon_of(const ParamSet& params) const {
  // Negative: the paper's default, the squared sample spacing.
  const double knob = params.real("epsilon");
  return static_cast<float>(knob >= 0.0 ? knob : samples_.spacing * samples_.spacing);
}

void PinholeMethod::fill_receivers(const GBuffer& gbuffer, const ParamSet& params, PinholeFrameData& frame) const {
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  frame.epsilon = epsilon_of(params);
  frame.area = samples_.samples.empty() ? 0.0f : samples_.samples.front().area;
  frame.attenuation = params.boolean("attenuation") ? 1 : 0;
  frame.fresnel = params.boolean("fresnel") ? 1 : 0;
  // 0 reflect, 1 refract, 2 auto: the shader refracts at glass materials (pinhole_refracts).
  frame.refraction = interaction_ == "refract" ? 1 : interaction_ == "auto" ? 2 : 0;
}

}  // namespace causticbench
