// The reference's lifecycle and its passes until the error target; the estimators are in
// reference_estimators.cpp, the knobs in reference_info.cpp.
#include "methods/reference/reference.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/image_statistics.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "methods/common/photon_memory.h"
#include "methods/reference/path_class_tally.h"
#include "methods/reference/reference_estimators.h"

namespace causticbench {

const char* const kReferenceErrorDefinition =
    "estimated relMSE of the result against the pixel's true footprint-average E_c (docs/metrics.md): per pixel the "
    "variance (footprint: from the spread of independent passes under stratified emission, from the second moment of "
    "the photons' contributions under random emission; ppm: (A - B)^2 / 4 of two independent halves) plus, for ppm, the squared bias beyond both variances against a footprint tally of the same photons, "
    "divided by value^2 + (0.1 mean)^2 as relMSE does; error_estimate = variance_estimate + bias_estimate";

void ReferenceMethod::check_scene(const Scene& scene) const {}

void ReferenceMethod::prepare(const PrepareContext& context, const ParamSet& build) {}

// A pass traces its photons into one vector, cleared before the next stream: the trace's peak
// (methods/common/photon_memory.h) for one stream's photons. Crediting (12 bytes a photon) and ppm's
// grid (at most 40) stay below it.
std::vector<MemoryTerm> ReferenceMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double per_pass = static_cast<double>(knobs.integer("photons_per_pass"));
  const double stream = knobs.text("estimator") == "ppm" ? std::max(1.0, std::floor(per_pass / 2.0)) : per_pass;
  const double deposits = deposits_per_photon_bound(context, static_cast<uint64_t>(knobs.integer("seed")) * 2,
                                                    static_cast<int>(knobs.integer("max_bounces")));
  // The paths occluders block (the occlusion split, core/path_classes.h) are held beside them: counted on a
  // pilot of 16,384 photons with a quarter's margin, as the deposits are.
  constexpr uint64_t kPilot = 16384;
  const CausticPhotonTracer pilot(context.tracer, PhotonTracerSettings{static_cast<uint64_t>(knobs.integer("seed")) * 2,
                                                                       static_cast<int>(knobs.integer("max_bounces"))});
  std::vector<Photon> photons;
  std::vector<uint8_t> classes;
  CausticPhotonTracer::Blocked blocked;
  PhotonStats stats;
  pilot.trace(0, kPilot, photons, stats, classes, &blocked);
  const double blocked_each = 1.25 * static_cast<double>(blocked.photons.size()) / static_cast<double>(kPilot);
  std::vector<MemoryTerm> terms = {
      MemoryTerm{{"photons_per_pass"}, stream * deposits * kBytesPerTracedPhoton,
                 fmt::format("{:.3g} photons a stream x {:.2f} deposited each at most x {:.0f} bytes", stream, deposits,
                             kBytesPerTracedPhoton)}};
  if (blocked_each > 0.0)
    terms.push_back(MemoryTerm{{"photons_per_pass"}, stream * blocked_each * kBytesPerTracedPhoton,
                               fmt::format("{:.3g} photons a stream x {:.2f} blocked paths each x {:.0f} bytes "
                                           "(the occlusion split)",
                                           stream, blocked_each, kBytesPerTracedPhoton)});
  return terms;
}

void ReferenceMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  tracer_ = &frame.tracer;
  camera_ = &frame.frame.camera;
}

Image ReferenceMethod::render(const GBuffer& gbuffer, const ParamSet& params) {
  auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const bool progressive = params.text("estimator") == "ppm";
  const uint64_t photons_per_pass = static_cast<uint64_t>(params.integer("photons_per_pass"));
  // ppm runs two independent halves (seeds 2s and 2s+1); footprint one stream of seed 2s.
  const uint64_t photons_per_stream = progressive ? std::max<uint64_t>(1, photons_per_pass / 2) : photons_per_pass;
  const int streams = progressive ? 2 : 1;
  const double target = params.real("target_error");
  const double max_seconds = params.real("max_seconds");
  const int64_t max_passes = params.integer("max_passes"), min_passes = params.integer("min_passes");
  const uint64_t seed = static_cast<uint64_t>(params.integer("seed"));
  const int max_bounces = static_cast<int>(params.integer("max_bounces"));

  const MeasurementPoints points(gbuffer);
  FootprintTally tally(points.size());
  std::vector<ProgressiveEstimator> halves;
  if (progressive)
    for (int h = 0; h < 2; ++h) halves.emplace_back(points, gbuffer, params.real("initial_radius_pixels"));
  memory_bytes_ = points.size() * (sizeof(uint32_t) + 2 * sizeof(Vec3) + 5 * sizeof(glm::dvec3) +
                                   (progressive ? 2 * (sizeof(double) + sizeof(float) + sizeof(glm::dvec3)) : 0)) +
                  gbuffer.pixel_count() * (sizeof(int32_t) + sizeof(uint8_t));
  std::vector<CausticPhotonTracer> photon_tracers;
  // Stratified emission: each stream's pass is one replicate of photons_per_stream photons spread evenly
  // over the emission (core/low_discrepancy.h); the replicates are independent of each other.
  const bool stratified = params.text("emission") == "stratified";
  for (int h = 0; h < streams; ++h) {
    PhotonTracerSettings settings{seed * 2 + h, max_bounces};
    if (stratified) settings.stratified_pass_size = photons_per_stream;
    photon_tracers.emplace_back(*tracer_, settings);
  }
  // The tally's variance: the spread of its replicates once there are two (the only honest measure under
  // stratified emission, and exact for random emission too, where it is also the photons' second moment's
  // job); before that, the photons' second moment, which overstates a stratified pass's variance.
  auto tally_variance_of = [&](size_t point) {
    return stratified && tally.replicates() >= 2 ? tally.replicate_variance(point) : tally.photon_variance(point);
  };

  ErrorImage error;
  auto estimate_error = [&] {
    error.value.resize(points.size());
    error.squared_error.resize(points.size());
    error.variance.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const glm::dvec3 tally_value = tally.value(i), tally_variance = tally_variance_of(i);
      if (!progressive) {
        error.value[i] = tally_value;
        error.variance[i] = error.squared_error[i] = tally_variance;
        continue;
      }
      const glm::dvec3 a = halves[0].value(i), b = halves[1].value(i), c = 0.5 * (a + b);
      // For independent halves, (A - C)^2 = (A - B)^2 / 4 has the expectation of C's variance. The
      // bias against the pixel's footprint average: what the difference to the unbiased tally of the
      // same photons holds beyond both estimates' variances.
      const glm::dvec3 variance = 0.25 * (a - b) * (a - b);
      const glm::dvec3 bias2 = glm::max((c - tally_value) * (c - tally_value) - variance - tally_variance, glm::dvec3(0.0));
      error.value[i] = c;
      error.variance[i] = variance;
      error.squared_error[i] = variance + bias2;
    }
  };

  PhotonStats stats;
  std::vector<Photon> photons;
  std::vector<uint8_t> classes;   // each photon's path class (core/path_classes.h)
  std::vector<int32_t> targets;   // each photon's point, -1 where not in view; released after each stream
  std::vector<double> weights, blocked_weights;  // pixels per unit area where each (blocked) photon is seen
  CausticPhotonTracer::Blocked blocked;  // the paths occluders block, followed on (core/path_classes.h)
  PathClassTally path_classes;
  nlohmann::json history = nlohmann::json::array();
  Progress progress("reference", 1.0);
  double trace_seconds = 0.0, credit_seconds = 0.0;
  uint64_t credited = 0;
  std::string stop_reason = "max_passes";
  int64_t pass = 0;
  error_estimate_ = variance_estimate_ = 0.0;
  while (true) {
    for (int h = 0; h < streams; ++h) {
      photons.clear();
      classes.clear();
      blocked.photons.clear();
      blocked.classes.clear();
      auto trace_start = std::chrono::steady_clock::now();
      photon_tracers[h].trace(static_cast<uint64_t>(pass) * photons_per_stream, photons_per_stream, photons, stats,
                              classes, &blocked);
      auto credit_start = std::chrono::steady_clock::now();
      trace_seconds += std::chrono::duration<double>(credit_start - trace_start).count();
      if (points.size() > 0) credited += tally.credit(points, *camera_, *tracer_, photons, &targets, &weights);
      tally.end_replicate(photons_per_stream);
      const std::vector<int32_t> blocked_targets =
          points.size() > 0 ? FootprintTally::locate(points, *camera_, *tracer_, blocked.photons, &blocked_weights)
                            : std::vector<int32_t>(blocked.photons.size(), -1);
      path_classes.add_replicate(photons, classes, PathClassTally::InView{targets, weights}, blocked,
                                 PathClassTally::InView{blocked_targets, blocked_weights}, photons_per_stream);
      // Not held while the next stream traces (knob_memory's bound).
      std::vector<int32_t>().swap(targets);
      std::vector<double>().swap(weights);
      std::vector<double>().swap(blocked_weights);
      credit_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - credit_start).count();
      if (progressive) {
        halves[h].add_emitted(photons_per_stream);
        halves[h].gather(points, photons, params.real("alpha"));
      }
    }
    ++pass;
    estimate_error();
    error_estimate_ = estimated_relative_mse(error.value, error.squared_error);
    variance_estimate_ = estimated_relative_mse(error.value, error.variance);
    double seconds = elapsed();
    history.push_back({{"pass", pass}, {"photons", streams * photons_per_stream * pass}, {"seconds", seconds},
                       {"error_estimate", error_estimate_}, {"variance_estimate", variance_estimate_}});
    double fraction = 0.0;
    if (target > 0.0 && error_estimate_ > target && pass >= 4) {
      // The error falls as a power of the time spent: fit its exponent over the second half of the
      // history and extrapolate the time at which it reaches the target.
      const auto& earlier = history[static_cast<size_t>(pass / 2)];
      double t0 = earlier["seconds"].get<double>(), f0 = earlier["error_estimate"].get<double>();
      double exponent = f0 > 0.0 && seconds > t0 ? std::log(f0 / error_estimate_) / std::log(seconds / t0) : 0.0;
      if (exponent > 0.0) fraction = seconds / (seconds * std::pow(error_estimate_ / target, 1.0 / exponent));
    } else if (target > 0.0 && error_estimate_ <= target) {
      fraction = 1.0;
    }
    if (max_seconds > 0.0) fraction = std::max(fraction, seconds / max_seconds);
    fraction = std::max(fraction, static_cast<double>(pass) / static_cast<double>(max_passes));
    progress.update_fraction(fraction, fmt::format("pass {} error {:.3g} (target {:.3g})", pass, error_estimate_, target));
    if (pass >= min_passes && target > 0.0 && error_estimate_ <= target) {
      stop_reason = "target_error";
      break;
    }
    if (max_seconds > 0.0 && seconds >= max_seconds) {
      stop_reason = "max_seconds";
      break;
    }
    if (pass >= max_passes) break;
  }
  progress.finish(fmt::format("{} passes, estimated error {:.3g}, stopped on {}", pass, error_estimate_, stop_reason));
  Image result(gbuffer.width, gbuffer.height, 3);
  write_points(points, error.value, false, result);
  error_map_ = Image(gbuffer.width, gbuffer.height, 3);
  write_points(points, error.squared_error, true, error_map_);
  double seconds = elapsed();
  photons_emitted_ = stats.emitted;
  photons_deposited_ = stats.deposited;
  photons_credited_ = credited;
  passes_ = static_cast<uint64_t>(pass);
  record_ = {{"estimator", params.text("estimator")},
             {"emission", params.text("emission")},
             {"passes", pass},
             {"photons_emitted", stats.emitted},
             {"photons_deposited", stats.deposited},
             {"photons_credited", credited},
             {"rays_traced", stats.rays},
             {"seconds", seconds},
             {"photon_tracing_seconds", trace_seconds},
             {"crediting_seconds", credit_seconds},
             {"photons_per_second", trace_seconds > 0.0 ? stats.emitted / trace_seconds : 0.0},
             {"credited_per_second", credit_seconds > 0.0 ? credited / credit_seconds : 0.0},
             {"error_estimate", error_estimate_},
             {"variance_estimate", variance_estimate_},
             {"bias_estimate", error_estimate_ - variance_estimate_},
             {"error_definition", kReferenceErrorDefinition},
             {"stop_reason", stop_reason},
             {"measurement_points", points.size()},
             {"path_classes", path_classes.to_json()},
             {"history", history}};
  return result;
}

Counters ReferenceMethod::counters() const {
  return {{"photons_emitted", static_cast<double>(photons_emitted_)},
          {"photons_deposited", static_cast<double>(photons_deposited_)},
          {"photons_credited", static_cast<double>(photons_credited_)},
          {"passes", static_cast<double>(passes_)}};
}

}  // namespace causticbench
