#include "methods/pinhole/pinhole.h"

#include <emmintrin.h>

#include <fmt/format.h>

#include "core/optics.h"
#include "core/parallel.h"

namespace causticbench {

PinholeMethod::PinholeMethod() = default;
PinholeMethod::~PinholeMethod() = default;

const MethodInfo& PinholeMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "pinhole";
    m.paper = "M. Wand, W. Strasser, \"Real-Time Caustics\", Computer Graphics Forum 22(3), 2003";
    m.summary = "Samples the reflector every frame; each sample projects the light's environment map onto the "
                "receivers like a pinhole camera, optionally with curvature-based anisotropic filtering.";
    const ParamPhase build = ParamPhase::build, render = ParamPhase::render;
    m.params = {
        ParamSpec::integer("samples", 1000, 1, 1e7, "target number of reflector samples (pinhole cameras) per frame", build),
        ParamSpec::choice("sampling", "neighborhood", {"random", "grid", "quantized_grid", "neighborhood"},
                          "stratification of the samples (Section 3.2)", build),
        ParamSpec::choice("filtering", "none", {"none", "isotropic", "anisotropic"},
                          "resampling filter of the light lookups from differential point samples (Section 3.3)", build),
        ParamSpec::choice("interaction", "reflect", {"reflect", "refract"},
                          "one mirror reflection, or one refraction (the variant Section 5 names)", build),
        ParamSpec::integer("environment_resolution", 256, 4, 4096, "cube map face size of the light map (paper: 256)", build),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of the reflector sampling", build),
        ParamSpec::real("epsilon", -1.0, -1.0, 1e6,
                        "added to the squared distance against the singularity; -1: the squared sample spacing A/N", render),
        ParamSpec::boolean("attenuation", true, "cosines over squared distance; false reproduces Fig. 5", render),
        ParamSpec::boolean("fresnel", true, "angle-dependent reflectance (conductor or dielectric Fresnel)", render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = true;
    c.refraction = true;
    c.multiple_bounces = false;
    c.directional_light = c.point_light = c.environment_light = true;
    c.moving_light = c.moving_objects = true;
    c.occlusion = false;
    c.non_lambertian_receivers = false;
    c.notes = {{"refraction", "a single refraction (interaction: refract), e.g. a water surface over a pool floor"},
               {"point_light", "approximated as distant from the reflectors' centre, as the paper does"},
               {"occlusion", "no visibility between reflector samples and receivers beyond back-face culling"},
               {"multiple_bounces", "one specular interaction only"}};
    return m;
  }();
  return info;
}

std::vector<int> pinhole_reflectors(const Scene& scene, const std::string& interaction) {
  std::vector<int> objects;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    MaterialKind kind = scene.objects[i].material.kind;
    bool reflects = kind == MaterialKind::mirror || kind == MaterialKind::diffuse_mirror || kind == MaterialKind::glass;
    if (interaction == "refract" ? kind == MaterialKind::glass : reflects) objects.push_back(static_cast<int>(i));
  }
  return objects;
}

void PinholeMethod::check_scene(const Scene& scene) const {
  for (const char* interaction : {"reflect", "refract"}) {
    std::vector<int> objects = pinhole_reflectors(scene, interaction);
    if (objects.empty()) continue;
    SceneFrame frame(scene, 0);
    for (int object : objects) {
      if (!(object_area(frame, object) > 0.0)) {
        throw InputError(fmt::format("{}: object '{}' is a reflector of zero area: pinhole cannot sample it",
                                     scene.source, scene.objects[object].name));
      }
    }
  }
}

void PinholeMethod::prepare(const Scene& scene, const ParamSet& build) {
  build_ = build;
  scene_ = &scene;
  if (pinhole_reflectors(scene, build.text("interaction")).empty()) {
    throw InputError(fmt::format("{}: pinhole with interaction '{}' needs at least one {} object", scene.source,
                                 build.text("interaction"), build.text("interaction") == "refract" ? "glass" : "specular"));
  }
}

void PinholeMethod::update(const FrameContext& context) {
  std::vector<int> objects = pinhole_reflectors(*scene_, build_.text("interaction"));
  samples_ = sample_reflectors(context.frame, objects, static_cast<size_t>(build_.integer("samples")),
                               parse_sampling_strategy(build_.text("sampling")), static_cast<uint64_t>(build_.integer("seed")));
  sample_materials_.clear();
  for (const ReflectorSample& sample : samples_.samples) sample_materials_.push_back(&scene_->objects[sample.object].material);
  // The light is distant from the reflectors' centre (the area-weighted mean of their samples).
  Vec3 center(0.0f);
  for (const ReflectorSample& sample : samples_.samples) center += sample.position;
  if (!samples_.samples.empty()) center /= static_cast<float>(samples_.samples.size());
  DistantLights lights(context.frame, center);
  cube_map_ = LightCubeMap(lights, static_cast<int>(build_.integer("environment_resolution")));
  filtered_map_.reset();
  if (build_.text("filtering") != "none") {
    // The denser neighbourhood for the regression: three sample spacings across.
    estimate_differentials(samples_, 1.5 * samples_.spacing);
    filtered_map_ = std::make_unique<FilteredLightMap>(lights, static_cast<int>(build_.integer("environment_resolution")) * 2);
  } else {
    samples_.dense.clear();
    samples_.dense.shrink_to_fit();
  }
}

namespace {

struct Interaction {
  bool refract = false;
  bool fresnel = true;
};

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

// The fraction of radiance carried: reflectance, or transmittance times the radiance compression n^2.
inline Color light_throughput(const Material& material, const Interaction& interaction, float cos_sample) {
  float cosine = interaction.fresnel ? cos_sample : 1.0f;
  if (interaction.refract) {
    return Color((1.0f - fresnel_dielectric(cosine, 1.0f / material.ior)) * material.ior * material.ior);
  }
  if (material.kind == MaterialKind::glass) return Color(fresnel_dielectric(cosine, material.ior));
  return material.mirror_reflectance(cosine);
}

// The geometric part of the unfiltered reflection for one receiver point and a block of samples:
// the cube-map face and texel coordinates of the direction towards the light (the arithmetic of
// LightCubeMap::direction_to_texel) and the weight cos cos A / (d^2 + e), zero where either side faces
// away. Four samples at a time with SSE2 (every x86-64 has it); GCC 12 does not vectorise the scalar
// form of this loop by itself. `count` must be a multiple of 4 (the arrays are padded).
void reflection_block(size_t count, const float* px, const float* py, const float* pz, const float* nx,
                      const float* ny, const float* nz, const float* two_sided, Vec3 x, Vec3 receiver_normal,
                      float epsilon, float area, bool attenuation, float resolution, int* face, float* texel_s,
                      float* texel_t, float* weight, float* cos_sample) {
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f), two = _mm_set1_ps(2.0f);
  const __m128 sign_bit = _mm_set1_ps(-0.0f);
  const __m128 xx = _mm_set1_ps(x.x), xy = _mm_set1_ps(x.y), xz = _mm_set1_ps(x.z);
  const __m128 rx = _mm_set1_ps(receiver_normal.x), ry = _mm_set1_ps(receiver_normal.y), rz = _mm_set1_ps(receiver_normal.z);
  const __m128 eps = _mm_set1_ps(epsilon), area4 = _mm_set1_ps(area), half_resolution = _mm_set1_ps(0.5f * resolution);
  auto select = [](__m128 mask, __m128 a, __m128 b) { return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b)); };
  for (size_t i = 0; i < count; i += 4) {
    __m128 ox = _mm_sub_ps(_mm_loadu_ps(px + i), xx), oy = _mm_sub_ps(_mm_loadu_ps(py + i), xy),
           oz = _mm_sub_ps(_mm_loadu_ps(pz + i), xz);
    __m128 distance2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(ox, ox), _mm_mul_ps(oy, oy)), _mm_mul_ps(oz, oz));
    __m128 inverse = _mm_div_ps(one, _mm_sqrt_ps(distance2));
    __m128 dx = _mm_mul_ps(ox, inverse), dy = _mm_mul_ps(oy, inverse), dz = _mm_mul_ps(oz, inverse);
    __m128 cos_receiver = _mm_add_ps(_mm_add_ps(_mm_mul_ps(rx, dx), _mm_mul_ps(ry, dy)), _mm_mul_ps(rz, dz));
    __m128 snx = _mm_loadu_ps(nx + i), sny = _mm_loadu_ps(ny + i), snz = _mm_loadu_ps(nz + i);
    __m128 cs = _mm_sub_ps(zero, _mm_add_ps(_mm_add_ps(_mm_mul_ps(snx, dx), _mm_mul_ps(sny, dy)), _mm_mul_ps(snz, dz)));
    // Two-sided samples seen from behind: flip the normal (cs becomes -cs; 2 cs n is unchanged).
    __m128 flip = _mm_and_ps(_mm_cmplt_ps(cs, zero), _mm_cmpgt_ps(_mm_loadu_ps(two_sided + i), half));
    __m128 twice = _mm_mul_ps(two, cs);
    cs = select(flip, _mm_sub_ps(zero, cs), cs);
    __m128 wx = _mm_add_ps(dx, _mm_mul_ps(twice, snx)), wy = _mm_add_ps(dy, _mm_mul_ps(twice, sny)),
           wz = _mm_add_ps(dz, _mm_mul_ps(twice, snz));
    __m128 ax = _mm_andnot_ps(sign_bit, wx), ay = _mm_andnot_ps(sign_bit, wy), az = _mm_andnot_ps(sign_bit, wz);
    __m128 x_major = _mm_and_ps(_mm_cmpge_ps(ax, ay), _mm_cmpge_ps(ax, az));
    __m128 y_major = _mm_andnot_ps(x_major, _mm_cmpge_ps(ay, az));
    __m128 major = select(x_major, ax, select(y_major, ay, az));
    __m128 x_positive = _mm_cmpgt_ps(wx, zero), y_positive = _mm_cmpgt_ps(wy, zero), z_positive = _mm_cmpgt_ps(wz, zero);
    __m128 minus_wx = _mm_sub_ps(zero, wx), minus_wz = _mm_sub_ps(zero, wz), minus_wy = _mm_sub_ps(zero, wy);
    __m128 sc = select(x_major, select(x_positive, minus_wz, wz), select(y_major, wx, select(z_positive, wx, minus_wx)));
    __m128 tc = select(y_major, select(y_positive, wz, minus_wz), minus_wy);
    __m128 face_value = select(x_major, select(x_positive, zero, one),
                               select(y_major, select(y_positive, _mm_set1_ps(2.0f), _mm_set1_ps(3.0f)),
                                      select(z_positive, _mm_set1_ps(4.0f), _mm_set1_ps(5.0f))));
    __m128 scale = _mm_div_ps(half_resolution, major);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(face + i), _mm_cvttps_epi32(face_value));
    _mm_storeu_ps(texel_s + i, _mm_add_ps(_mm_mul_ps(sc, scale), half_resolution));
    _mm_storeu_ps(texel_t + i, _mm_add_ps(_mm_mul_ps(tc, scale), half_resolution));
    __m128 geometry = attenuation ? _mm_div_ps(_mm_mul_ps(cs, cos_receiver), _mm_add_ps(distance2, eps)) : one;
    __m128 facing = _mm_and_ps(_mm_cmpgt_ps(cos_receiver, zero), _mm_cmpgt_ps(cs, zero));
    _mm_storeu_ps(weight + i, _mm_and_ps(facing, _mm_mul_ps(geometry, area4)));
    _mm_storeu_ps(cos_sample + i, cs);
  }
}

}  // namespace

Image PinholeMethod::render(const GBuffer& gbuffer, const ParamSet& params) {
  Image result(gbuffer.width, gbuffer.height, 3);
  const std::vector<ReflectorSample>& samples = samples_.samples;
  if (samples.empty()) return result;
  const double epsilon_knob = params.real("epsilon");
  const float epsilon = static_cast<float>(epsilon_knob >= 0.0 ? epsilon_knob : samples_.spacing * samples_.spacing);
  const bool attenuation = params.boolean("attenuation");
  Interaction interaction{build_.text("interaction") == "refract", params.boolean("fresnel")};
  const std::string& filtering = build_.text("filtering");
  const bool filtered = filtering != "none" && filtered_map_;
  const bool anisotropic = filtering == "anisotropic";
  const float footprint_radius = static_cast<float>(0.5 * samples_.spacing);
  // Structure of arrays for the hot loop (pixels x samples): positions and normals contiguous.
  const size_t count = samples.size();
  // Padded to a multiple of 4 for the SSE kernel; padding samples have a zero normal, so they never face.
  const size_t padded = (count + 3) / 4 * 4;
  std::vector<float> px(padded, 0.0f), py(padded, 0.0f), pz(padded, 1e30f), nx(padded, 0.0f), ny(padded, 0.0f),
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
  if (!filtered && !interaction.refract) {
    // The common case (Fig. 4 to 7): geometry in vectorised blocks, then a lookup per facing sample.
    constexpr size_t kBlock = 256;
    parallel_blocks(gbuffer.pixel_count(), 64, [&](size_t begin, size_t end, size_t) {
      alignas(32) float texel_s[kBlock], texel_t[kBlock], weight[kBlock], cos_sample[kBlock];
      alignas(32) int face[kBlock];
      uint16_t indices[kBlock];
      const float resolution = static_cast<float>(cube_map_.resolution());
      for (size_t pixel = begin; pixel < end; ++pixel) {
        if (!gbuffer.receiver[pixel]) continue;
        Color sum(0.0f);
        for (size_t first = 0; first < count; first += kBlock) {
          size_t n = std::min(kBlock, count - first);
          reflection_block((n + 3) / 4 * 4, &px[first], &py[first], &pz[first], &nx[first], &ny[first], &nz[first], &two_sided[first],
                           gbuffer.position[pixel], gbuffer.normal[pixel], epsilon, sample_area, attenuation, resolution,
                           face, texel_s, texel_t, weight, cos_sample);
          // Compact the facing samples without a branch (about half face away, at random, which a
          // branch would mispredict), then look them up.
          size_t facing = 0;
          for (size_t j = 0; j < n; ++j) {
            indices[facing] = static_cast<uint16_t>(j);
            facing += weight[j] > 0.0f ? 1 : 0;
          }
          for (size_t k = 0; k < facing; ++k) {
            size_t j = indices[k];
            Color radiance = cube_map_.lookup_texel(face[j], texel_s[j], texel_t[j]);
            if (radiance.r + radiance.g + radiance.b <= 0.0f) continue;
            sum += radiance * light_throughput(*sample_materials_[first + j], interaction, cos_sample[j]) * weight[j];
          }
        }
        result.set_rgb(pixel, sum);
      }
    });
    evaluations_ = static_cast<double>(gbuffer.receiver_count()) * static_cast<double>(count);
    return result;
  }
  parallel_blocks(gbuffer.pixel_count(), 64, [&](size_t begin, size_t end, size_t) {
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      const Vec3 x = gbuffer.position[pixel], receiver_normal = gbuffer.normal[pixel];
      Color sum(0.0f);
      for (size_t i = 0; i < count; ++i) {
        Vec3 offset(px[i] - x.x, py[i] - x.y, pz[i] - x.z);
        float distance2 = glm::dot(offset, offset);
        float cos_receiver_scaled = glm::dot(receiver_normal, offset);
        if (cos_receiver_scaled <= 0.0f) continue;  // back-face culling at the receiver, before any root
        const ReflectorSample& sample = samples[i];
        Vec3 direction = offset * (1.0f / std::sqrt(distance2));
        float cos_receiver = glm::dot(receiver_normal, direction);
        const Material& material = *sample_materials_[i];
        Vec3 to_light;
        float cos_sample;
        if (!light_direction(direction, Vec3(nx[i], ny[i], nz[i]), sample.two_sided, material.ior, interaction.refract,
                             to_light, cos_sample)) {
          continue;
        }
        Color radiance;
        if (filtered) {
          // Differential point sample: reflection (or refraction) directions at p + r u and p + r v
          // with the normals n + r dn/du and n + r dn/dv give the footprint's two gradients.
          Vec3 gradients[2];
          const Vec3 axes[2] = {sample.direction_u, sample.direction_v};
          const Vec3 derivatives[2] = {sample.normal_derivative_u, sample.normal_derivative_v};
          for (int k = 0; k < 2; ++k) {
            Vec3 moved = sample.position + footprint_radius * axes[k] - x;
            Vec3 moved_normal = glm::normalize(sample.normal + footprint_radius * derivatives[k]);
            Vec3 moved_light;
            float unused_cos;
            gradients[k] = light_direction(glm::normalize(moved), moved_normal, sample.two_sided, material.ior,
                                           interaction.refract, moved_light, unused_cos)
                               ? moved_light - to_light
                               : Vec3(0.0f);
          }
          radiance = filtered_map_->lookup(to_light, gradients[0], gradients[1], anisotropic);
        } else {
          radiance = cube_map_.lookup(to_light);
        }
        if (radiance.r + radiance.g + radiance.b <= 0.0f) continue;
        float geometry = attenuation ? cos_sample * cos_receiver / (distance2 + epsilon) : 1.0f;
        sum += radiance * light_throughput(material, interaction, cos_sample) * (geometry * sample.area);
      }
      result.set_rgb(pixel, sum);
    }
  });
  evaluations_ = static_cast<double>(gbuffer.receiver_count()) * static_cast<double>(samples.size());
  return result;
}

size_t PinholeMethod::memory_bytes() const {
  return samples_.samples.size() * (sizeof(ReflectorSample) + sizeof(const Material*)) + cube_map_.memory_bytes() +
         (filtered_map_ ? filtered_map_->memory_bytes() : 0);
}

Counters PinholeMethod::counters() const {
  return {{"samples", static_cast<double>(samples_.samples.size())},
          {"cube_map_texels", static_cast<double>(cube_map_.texels().size() / 3)},
          {"sample_evaluations", evaluations_}};
}

nlohmann::json PinholeMethod::record() const {
  return {{"samples", samples_.samples.size()},
          {"reflector_area", samples_.total_area},
          {"sample_spacing", samples_.spacing},
          {"cell_or_diameter", samples_.cell_or_diameter}};
}

}  // namespace causticbench
