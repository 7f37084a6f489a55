#include "methods/reference/reference.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/image_statistics.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "methods/common/photon_grid.h"

namespace causticbench {

namespace {

// Per measurement point state of one progressive photon mapping estimator (Hachisuka et al. 2008,
// Section 4.2): accumulated photon count N, squared radius R^2 and radius-corrected flux tau.
struct Estimator {
  uint64_t seed = 0;
  std::vector<double> count;
  std::vector<float> radius2;
  std::vector<glm::dvec3> flux;
  uint64_t emitted = 0;
};

struct MeasurementPoints {
  std::vector<uint32_t> pixel;
  std::vector<Vec3> position;
  std::vector<Vec3> normal;
};

float median_radius(const std::vector<float>& radius2) {
  std::vector<float> copy = radius2;
  std::nth_element(copy.begin(), copy.begin() + copy.size() / 2, copy.end());
  return std::sqrt(copy[copy.size() / 2]);
}

// One PPM pass: every measurement point collects the new photons within its radius, then shrinks its
// radius keeping the fraction alpha of them (the radius-reduction step of the paper).
void gather(const MeasurementPoints& points, const std::vector<Photon>& photons, double alpha, Estimator& estimator) {
  if (photons.empty()) return;
  PhotonGrid grid(photons, std::max(1e-7f, median_radius(estimator.radius2)));
  parallel_blocks(points.position.size(), 512, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const Vec3 point = points.position[i], normal = points.normal[i];
      const float radius2 = estimator.radius2[i];
      uint64_t found = 0;
      glm::dvec3 flux(0.0);
      grid.for_each_near(point, std::sqrt(radius2), [&](const Photon& photon) {
        Vec3 offset = photon.position - point;
        // Same surface side as the camera sees it; the sphere test does the rest.
        if (glm::dot(offset, offset) >= radius2 || glm::dot(photon.normal, normal) < 0.7f) return;
        ++found;
        flux += glm::dvec3(photon.power);
      });
      if (found == 0) continue;
      double previous = estimator.count[i];
      double kept = previous + alpha * static_cast<double>(found);
      double ratio = kept / (previous + static_cast<double>(found));
      estimator.count[i] = kept;
      estimator.radius2[i] = static_cast<float>(radius2 * ratio);
      estimator.flux[i] = (estimator.flux[i] + flux) * ratio;
    }
  });
}

void estimate(const MeasurementPoints& points, const Estimator& estimator, Image& image) {
  double emitted = static_cast<double>(std::max<uint64_t>(1, estimator.emitted));
  for (size_t i = 0; i < points.pixel.size(); ++i) {
    double area = kPiDouble * estimator.radius2[i];
    image.set_rgb(points.pixel[i], Color(estimator.flux[i] / (area * emitted)));
  }
}

}  // namespace

const MethodInfo& ReferenceMethod::static_info() {
  static const MethodInfo info = [] {
    MethodInfo m;
    m.name = "reference";
    m.paper = "T. Hachisuka, S. Ogaki, H. W. Jensen, \"Progressive Photon Mapping\", ACM TOG 27(5), 2008";
    m.summary = "Converged caustic irradiance by progressive photon mapping over the G-buffer points; stops on "
                "its own noise floor, measured from two independent halves.";
    const ParamPhase render = ParamPhase::render;
    m.params = {
        ParamSpec::integer("photons_per_pass", 4000000, 1000, 1e9, "photons emitted per pass, split between the two halves", render),
        ParamSpec::real("target_noise_floor", 1e-3, 0.0, 1.0,
                        "stop when the estimated relMSE of the result (from the two halves) falls to this; 0: never", render),
        ParamSpec::real("max_seconds", 600.0, 0.0, 1e7, "stop after this much wall time (0: no limit)", render),
        ParamSpec::integer("max_passes", 100000, 1, 1e9, "stop after this many passes", render),
        ParamSpec::integer("min_passes", 4, 1, 1e6, "never stop on the noise floor before this many passes", render),
        ParamSpec::real("alpha", 2.0 / 3.0, 0.01, 1.0, "fraction of new photons kept per pass (radius reduction)", render),
        ParamSpec::real("initial_radius_pixels", 1.0, 0.05, 1000.0,
                        "initial gather radius in pixel footprints at each point", render),
        ParamSpec::integer("max_bounces", 32, 1, 1000, "specular bounces before a photon path is cut", render),
        ParamSpec::integer("seed", 1, 0, 4e9, "seed of every random choice", render),
    };
    Capabilities& c = m.capabilities;
    c.reflection = c.refraction = c.multiple_bounces = true;
    c.directional_light = c.point_light = c.environment_light = true;
    c.moving_light = c.moving_objects = c.occlusion = c.non_lambertian_receivers = true;
    c.notes = {{"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF"}};
    m.quick_knobs = {"photons_per_pass=20000", "max_passes=2", "target_noise_floor=0", "max_seconds=0"};
    // The per-pixel hit points and their progressive statistics (measured: docs/results-format.md, "Memory").
    m.working_bytes_per_pixel = 24.0;
    m.counters = {counter_quantity("photons_emitted", "photons", "photons emitted over all passes"),
                  counter_quantity("photons_deposited", "photons", "photon hits gathered on receivers over all passes"),
                  counter_quantity("passes", "passes", "progressive passes until the stop rule (stop_reason)")};
    return m;
  }();
  return info;
}

void ReferenceMethod::check_scene(const Scene& scene) const {}

void ReferenceMethod::prepare(const PrepareContext& context, const ParamSet& build) {}

void ReferenceMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) { tracer_ = &frame.tracer; }

Image ReferenceMethod::render(const GBuffer& gbuffer, const ParamSet& params) {
  auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const uint64_t photons_per_half = std::max<int64_t>(1, params.integer("photons_per_pass") / 2);
  const double target = params.real("target_noise_floor");
  const double max_seconds = params.real("max_seconds");
  const int64_t max_passes = params.integer("max_passes"), min_passes = params.integer("min_passes");
  const double alpha = params.real("alpha");
  const uint64_t seed = static_cast<uint64_t>(params.integer("seed"));

  MeasurementPoints points;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    points.pixel.push_back(static_cast<uint32_t>(pixel));
    points.position.push_back(gbuffer.position[pixel]);
    points.normal.push_back(gbuffer.normal[pixel]);
  }
  Estimator halves[2];
  for (int h = 0; h < 2; ++h) {
    halves[h].seed = seed * 2 + h;
    halves[h].count.assign(points.pixel.size(), 0.0);
    halves[h].flux.assign(points.pixel.size(), glm::dvec3(0.0));
    halves[h].radius2.resize(points.pixel.size());
    for (size_t i = 0; i < points.pixel.size(); ++i) {
      float radius = static_cast<float>(params.real("initial_radius_pixels")) * gbuffer.footprint[points.pixel[i]];
      halves[h].radius2[i] = radius * radius;
    }
  }
  memory_bytes_ = points.pixel.size() * (sizeof(uint32_t) + 2 * sizeof(Vec3) +
                                         2 * (sizeof(double) + sizeof(float) + sizeof(glm::dvec3)));

  Image images[2] = {Image(gbuffer.width, gbuffer.height, 3), Image(gbuffer.width, gbuffer.height, 3)};
  Image combined(gbuffer.width, gbuffer.height, 3);
  PhotonStats stats;
  std::vector<Photon> photons;
  nlohmann::json history = nlohmann::json::array();
  Progress progress("reference", 1.0);
  double trace_seconds = 0.0;
  std::string stop_reason = "max_passes";
  int64_t pass = 0;
  noise_floor_ = 0.0;
  bool has_points = !points.pixel.empty();
  const int max_bounces = static_cast<int>(params.integer("max_bounces"));
  const CausticPhotonTracer photon_tracers[2] = {
      CausticPhotonTracer(*tracer_, PhotonTracerSettings{halves[0].seed, max_bounces}),
      CausticPhotonTracer(*tracer_, PhotonTracerSettings{halves[1].seed, max_bounces})};
  while (true) {
    for (int h = 0; h < 2; ++h) {
      photons.clear();
      auto trace_start = std::chrono::steady_clock::now();
      photon_tracers[h].trace(static_cast<uint64_t>(pass) * photons_per_half, photons_per_half, photons, stats);
      trace_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - trace_start).count();
      halves[h].emitted += photons_per_half;
      if (has_points) gather(points, photons, alpha, halves[h]);
    }
    ++pass;
    for (int h = 0; h < 2; ++h) estimate(points, halves[h], images[h]);
    for (size_t i = 0; i < combined.values().size(); ++i) {
      combined.values()[i] = 0.5f * (images[0].values()[i] + images[1].values()[i]);
    }
    // For independent halves A and B with variance s^2 each, the average C has variance s^2 / 2, and
    // (A - C)^2 = (A - B)^2 / 4 has exactly that expectation: relMSE(A, C) estimates C's relMSE.
    noise_floor_ = relative_mse(images[0], combined, gbuffer.receiver);
    double seconds = elapsed();
    history.push_back({{"pass", pass}, {"photons", 2 * photons_per_half * pass}, {"seconds", seconds},
                       {"noise_floor", noise_floor_}});
    double fraction = 0.0;
    if (target > 0.0 && noise_floor_ > target && pass >= 4) {
      // The floor falls as a power of the time spent: fit its exponent over the second half of the
      // history and extrapolate the time at which it reaches the target.
      const auto& earlier = history[static_cast<size_t>(pass / 2)];
      double t0 = earlier["seconds"].get<double>(), f0 = earlier["noise_floor"].get<double>();
      double exponent = f0 > 0.0 && seconds > t0 ? std::log(f0 / noise_floor_) / std::log(seconds / t0) : 0.0;
      if (exponent > 0.0) {
        double needed = seconds * std::pow(noise_floor_ / target, 1.0 / exponent);
        fraction = seconds / needed;
      }
    } else if (target > 0.0 && noise_floor_ <= target) {
      fraction = 1.0;
    }
    if (max_seconds > 0.0) fraction = std::max(fraction, seconds / max_seconds);
    fraction = std::max(fraction, static_cast<double>(pass) / static_cast<double>(max_passes));
    progress.update_fraction(fraction, fmt::format("pass {} noise floor {:.3g} (target {:.3g})", pass, noise_floor_, target));
    if (pass >= min_passes && target > 0.0 && noise_floor_ <= target) {
      stop_reason = "target_noise_floor";
      break;
    }
    if (max_seconds > 0.0 && seconds >= max_seconds) {
      stop_reason = "max_seconds";
      break;
    }
    if (pass >= max_passes) break;
  }
  progress.finish(fmt::format("{} passes, noise floor {:.3g}, stopped on {}", pass, noise_floor_, stop_reason));
  double seconds = elapsed();
  photons_emitted_ = stats.emitted;
  photons_deposited_ = stats.deposited;
  passes_ = static_cast<uint64_t>(pass);
  record_ = {{"passes", pass},
             {"photons_emitted", stats.emitted},
             {"photons_deposited", stats.deposited},
             {"rays_traced", stats.rays},
             {"seconds", seconds},
             {"photon_tracing_seconds", trace_seconds},
             {"photons_per_second", trace_seconds > 0.0 ? stats.emitted / trace_seconds : 0.0},
             {"noise_floor", noise_floor_},
             {"noise_floor_definition", "estimated relMSE of the result (A+B)/2 of two independent halves: relMSE(A, (A+B)/2)"},
             {"stop_reason", stop_reason},
             {"measurement_points", points.pixel.size()},
             {"history", history}};
  return combined;
}

Counters ReferenceMethod::counters() const {
  return {{"photons_emitted", static_cast<double>(photons_emitted_)},
          {"photons_deposited", static_cast<double>(photons_deposited_)},
          {"passes", static_cast<double>(passes_)}};
}

}  // namespace causticbench
