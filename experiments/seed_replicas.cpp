// Measuring a run with several seeds (declared in seed_replicas.h).
#include "experiments/seed_replicas.h"

#include <cmath>
#include <map>

#include <fmt/format.h>

#include "store/result_paths.h"

namespace causticbench {

namespace {

// The mean over the seeds of one set of metrics (a run's or a frame's): a value where every seed has
// one, else undefined with the first seed's reason that lacks it.
void mean_over_seeds(const std::vector<const std::map<std::string, double>*>& values,
                     const std::vector<const std::map<std::string, std::string>*>& undefined,
                     const std::vector<int64_t>& seeds, std::map<std::string, double>& mean,
                     std::map<std::string, std::string>& why, std::map<std::string, MetricInterval>* intervals) {
  mean.clear();
  why.clear();
  std::map<std::string, std::vector<double>> samples;
  for (size_t s = 0; s < values.size(); ++s)
    for (const auto& [name, value] : *values[s]) samples[name].push_back(value);
  for (size_t s = 0; s < undefined.size(); ++s)
    for (const auto& [name, reason] : *undefined[s])
      if (!why.count(name)) why[name] = seeds.size() > 1 ? fmt::format("seed {}: {}", seeds[s], reason) : reason;
  for (const auto& [name, list] : samples) {
    if (why.count(name)) continue;
    if (list.size() != values.size()) {
      why[name] = "not measured on every seed";
      continue;
    }
    bool finite = true;
    for (double value : list) finite = finite && std::isfinite(value);
    if (!finite) {
      mean[name] = std::nan("");  // a non-finite value (psnr of an exact image) on some seed: no mean
      continue;
    }
    const MetricInterval interval = interval_of(list);
    mean[name] = interval.mean;
    if (intervals) (*intervals)[name] = interval;
  }
}

}  // namespace

bool stochastic(const RunSpec& run) { return run.params.has("seed"); }

int seed_count(const Experiment& experiment, const RunSpec& run) { return stochastic(run) ? experiment.seeds : 1; }

RunSpec seed_replica(const RunSpec& run, int index) {
  RunSpec replica = run;
  if (index == 0) return replica;
  const int64_t seed = run.params.integer("seed") + index;
  replica.params.set("seed", seed);
  for (ParamSet* phase : {&replica.build, &replica.frame, &replica.render})
    if (phase->has("seed")) phase->set("seed", seed);
  return replica;
}

std::string seed_image_file(int64_t seed, int frame) {
  return ResultPaths::frame_file(frame, fmt::format("seed{}", seed)) + ".exr";
}

std::string stddev_image_file(int frame) { return ResultPaths::frame_file(frame, "stddev") + ".exr"; }

void aggregate_seeds(RunRecord& record) {
  SeedsRecord& seeds = *record.seeds;
  std::vector<int64_t> values;
  std::vector<const std::map<std::string, double>*> metrics;
  std::vector<const std::map<std::string, std::string>*> undefined;
  for (const SeedRun& run : seeds.runs) {
    values.push_back(run.seed);
    metrics.push_back(&run.metrics);
    undefined.push_back(&run.metrics_undefined);
  }
  seeds.intervals.clear();
  mean_over_seeds(metrics, undefined, values, record.metrics, record.metrics_undefined, &seeds.intervals);
  for (size_t f = 0; f < record.frames.size(); ++f) {
    metrics.clear();
    undefined.clear();
    for (const SeedRun& run : seeds.runs) {
      metrics.push_back(&run.frames.at(f).metrics);
      undefined.push_back(&run.frames.at(f).metrics_undefined);
    }
    mean_over_seeds(metrics, undefined, values, record.frames[f].metrics, record.frames[f].metrics_undefined, nullptr);
  }
}

RunOutcome combine_seeds(std::vector<RunOutcome> outcomes) {
  RunOutcome combined = std::move(outcomes.front());
  RunRecord& record = combined.record;
  for (size_t s = 1; s < outcomes.size(); ++s) {
    if (!outcomes[s].record.ok() && record.ok()) {
      record.status = "failed";
      record.error = fmt::format("seed {}: {}", outcomes[s].record.knobs().value("seed", int64_t{0}), outcomes[s].record.error);
    }
  }
  if (!record.ok()) {
    record.frames.clear();  // a failed run keeps its identity and why
    combined.images.clear();
    return combined;
  }
  SeedsRecord seeds;
  for (size_t s = 0; s < outcomes.size(); ++s) {
    const RunRecord& one = s == 0 ? record : outcomes[s].record;  // the first was moved into `combined`
    SeedRun run{one.knobs().at("seed").get<int64_t>(), one.frames, one.metrics, one.metrics_undefined};
    if (s > 0) {
      for (size_t f = 0; f < run.frames.size(); ++f) {
        run.frames[f].image = seed_image_file(run.seed, run.frames[f].frame);
        combined.more_images.push_back({run.frames[f].image, std::move(outcomes[s].images[f].second)});
      }
    }
    seeds.runs.push_back(std::move(run));
  }
  // The per-pixel standard deviation over the seeds of every frame, each channel on its own.
  for (size_t f = 0; f < combined.images.size(); ++f) {
    const Image& own = combined.images[f].second;
    std::vector<const Image*> images = {&own};
    for (size_t s = 1; s < outcomes.size(); ++s) images.push_back(&combined.more_images[(s - 1) * combined.images.size() + f].second);
    Image deviation(own.width(), own.height(), own.channels());
    const double n = static_cast<double>(images.size());
    for (size_t i = 0; i < own.values().size(); ++i) {
      double sum = 0.0, squares = 0.0;
      for (const Image* image : images) sum += image->values()[i];
      const double mean = sum / n;
      for (const Image* image : images) squares += (image->values()[i] - mean) * (image->values()[i] - mean);
      deviation.values()[i] = static_cast<float>(std::sqrt(squares / (n - 1.0)));
    }
    seeds.stddev_images.push_back(stddev_image_file(combined.images[f].first));
    combined.more_images.push_back({seeds.stddev_images.back(), std::move(deviation)});
  }
  record.seeds = std::move(seeds);
  aggregate_seeds(record);
  return combined;
}

}  // namespace causticbench
