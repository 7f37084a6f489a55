#include "methods/reference/path_class_tally.h"

#include <cmath>

namespace causticbench {

void PathClassTally::add_replicate(const std::vector<Photon>& photons, const std::vector<uint8_t>& classes,
                                   InView seen, const CausticPhotonTracer::Blocked& blocked, InView blocked_seen,
                                   uint64_t emitted) {
  Sums view, all;
  const double scale = 1.0 / static_cast<double>(std::max<uint64_t>(1, emitted));
  auto add = [](Sums& sums, const PathClass& path, double light_amount) {
    const auto interaction = static_cast<size_t>(path.interaction), light = static_cast<size_t>(path.light),
               receiver = static_cast<size_t>(path.receiver);
    sums.interaction[interaction] += light_amount;
    sums.light[light] += light_amount;
    sums.receiver[receiver] += light_amount;
    sums.joint[(interaction * kPathLights + light) * kPathReceivers + receiver] += light_amount;
    sums.total += light_amount;
  };
  // In view, the mean of the three channels, as the energy ratio sums an image (masked_sum); everywhere
  // the flux's luminance, as the probes behind lost flux count it.
  auto channel_mean = [](const Color& power) {
    return (static_cast<double>(power.r) + static_cast<double>(power.g) + static_cast<double>(power.b)) / 3.0;
  };
  for (size_t i = 0; i < photons.size() && i < classes.size(); ++i) {
    const PathClass path = PathClass::unpack(classes[i]);
    add(all, path, static_cast<double>(luminance(photons[i].power)) * scale);
    if (seen.seen(i)) add(view, path, channel_mean(photons[i].power) * scale * seen.weight(i));
  }
  for (size_t i = 0; i < blocked.photons.size(); ++i) {
    all.blocked += static_cast<double>(luminance(blocked.photons[i].power)) * scale;
    if (blocked_seen.seen(i)) view.blocked += channel_mean(blocked.photons[i].power) * scale * blocked_seen.weight(i);
  }
  in_view_.push_back(view);
  everywhere_.push_back(all);
}

namespace {

// The share of class flux F in the total T over R replicates, Σ F_r / Σ T_r, and the standard error of
// that ratio from the replicates' residuals F_r - share T_r (the delta method for a ratio of means).
template <class Pick, class Total>
nlohmann::json share_of(const std::vector<PathClassTally::Sums>& replicates, Pick pick, Total total,
                        const char* capability) {
  double class_sum = 0.0, total_sum = 0.0;
  for (const auto& sums : replicates) class_sum += pick(sums), total_sum += total(sums);
  const double share = total_sum > 0.0 ? class_sum / total_sum : 0.0;
  nlohmann::json entry = {{"share", share}, {"capability", capability}, {"standard_error", nullptr}};
  const size_t r = replicates.size();
  if (r >= 2 && total_sum > 0.0) {
    double residuals = 0.0;
    for (const auto& sums : replicates) {
      const double d = pick(sums) - share * total(sums);
      residuals += d * d;
    }
    const double mean_total = total_sum / static_cast<double>(r);
    entry["standard_error"] = std::sqrt(residuals / (static_cast<double>(r) * static_cast<double>(r - 1))) / mean_total;
  }
  return entry;
}

template <class Pick>
nlohmann::json share_of(const std::vector<PathClassTally::Sums>& replicates, Pick pick, const char* capability) {
  return share_of(replicates, pick, [](const PathClassTally::Sums& s) { return s.total; }, capability);
}

// `amount`: what the totals are ("pixel_sum" in view, "flux" everywhere).
nlohmann::json shares(const std::vector<PathClassTally::Sums>& replicates, const char* amount) {
  double total = 0.0, blocked = 0.0;
  for (const auto& sums : replicates) total += sums.total, blocked += sums.blocked;
  nlohmann::json out = {{amount, replicates.empty() ? 0.0 : total / static_cast<double>(replicates.size())},
                        {"replicates", replicates.size()}};
  for (int k = 0; k < kPathInteractions; ++k) {
    const auto interaction = static_cast<PathInteraction>(k);
    out["interaction"][path_interaction_name(interaction)] =
        share_of(replicates, [k](const PathClassTally::Sums& s) { return s.interaction[static_cast<size_t>(k)]; },
                 path_interaction_capability(interaction));
  }
  for (int k = 0; k < kPathLights; ++k) {
    const auto light = static_cast<PathLight>(k);
    out["light"][path_light_name(light)] =
        share_of(replicates, [k](const PathClassTally::Sums& s) { return s.light[static_cast<size_t>(k)]; },
                 path_light_capability(light));
  }
  for (int k = 0; k < kPathReceivers; ++k) {
    const auto receiver = static_cast<PathReceiver>(k);
    out["receiver"][path_receiver_name(receiver)] =
        share_of(replicates, [k](const PathClassTally::Sums& s) { return s.receiver[static_cast<size_t>(k)]; },
                 path_receiver_capability(receiver));
  }
  for (int i = 0; i < kPathInteractions; ++i)
    for (int k = 0; k < kPathLights; ++k)
      for (int r = 0; r < kPathReceivers; ++r) {
        const auto interaction = static_cast<PathInteraction>(i);
        const auto light = static_cast<PathLight>(k);
        const auto receiver = static_cast<PathReceiver>(r);
        const size_t index = static_cast<size_t>((i * kPathLights + k) * kPathReceivers + r);
        nlohmann::json entry =
            share_of(replicates, [index](const PathClassTally::Sums& s) { return s.joint[index]; }, "");
        entry.erase("capability");
        nlohmann::json capabilities = {path_interaction_capability(interaction), path_light_capability(light)};
        if (*path_receiver_capability(receiver)) capabilities.push_back(path_receiver_capability(receiver));
        entry["capabilities"] = capabilities;
        out["joint"][std::string(path_interaction_name(interaction)) + "/" + path_light_name(light) + "/" +
                     path_receiver_name(receiver)] = entry;
      }
  // The blocked light's share of the light that would arrive without occluders, and its ratio to the light
  // that does arrive (the most a method without occlusion may put out beyond the reference).
  nlohmann::json occlusion = share_of(
      replicates, [](const PathClassTally::Sums& s) { return s.blocked; },
      [](const PathClassTally::Sums& s) { return s.total + s.blocked; }, kOcclusionCapability);
  occlusion["excess"] = total > 0.0 ? blocked / total : 0.0;
  out["occlusion"] = occlusion;
  return out;
}

}  // namespace

nlohmann::json PathClassTally::to_json() const {
  return {{"definition", "share of the reference's caustic light in each light-path class: by "
                         "interaction (one_reflection: one reflection off an object's outside; one_pass: into one "
                         "refracting object and out with nothing between, or into an open surface's medium; "
                         "multiple: everything else), by the light's kind and by the receiver (lambertian: diffuse; "
                         "non_lambertian: glossy or diffuse_mirror); occlusion: the light occluders block between the "
                         "light and a specular object or between it and a receiver behind the one it reaches, followed "
                         "on as if they were not there; in view: the photons credited to a "
                         "receiver pixel, each weighted by its pixel's pixels per unit area as the image is, its "
                         "channels' mean (shares of the image's E_c summed as an energy ratio sums it); everywhere: "
                         "every photon's flux (luminance) deposited on a receiver; "
                         "standard_error from the spread of the passes (core/path_classes.h)"},
          {"in_view", shares(in_view_, "pixel_sum")},
          {"everywhere", shares(everywhere_, "flux")}};
}

}  // namespace causticbench
