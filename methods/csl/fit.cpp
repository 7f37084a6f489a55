#include "methods/csl/fit.h"

#include <algorithm>
#include <cmath>

#include <mutex>

#include <ceres/ceres.h>
#include <glog/logging.h>

namespace causticbench::csl {

namespace {

// One bundle ray's three residuals sqrt(w) sqrt(t1^2 + t2^2) (d - e) over (kappa, beta, l).
struct RayResidual {
  glm::dvec3 q, d, b, a;
  double reach, weight;

  template <typename T>
  bool operator()(const T* const kappa, const T* const beta, const T* const ell, T* residual) const {
    const double along = glm::dot(d, a);  // > 0: members are within 90 degrees of the axis
    // p = q + ((b - q).a + l) / (d.a) d; c = b + l a.
    const T travel = (T(glm::dot(b - q, a)) + ell[0]) / T(along);
    T from[3];  // p - c, perpendicular to a
    for (int k = 0; k < 3; ++k) from[k] = T(q[k]) + travel * T(d[k]) - (T(b[k]) + ell[0] * T(a[k]));
    const T r = ceres::sqrt(from[0] * from[0] + from[1] * from[1] + from[2] * from[2] + T(1e-30));
    const T g = kappa[0] * (T(1.0) + beta[0] * r);
    T e[3];
    for (int k = 0; k < 3; ++k) e[k] = T(a[k]) - g * from[k];
    const T length = ceres::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    const T t1 = ceres::abs(travel);
    const T t2 = t1 + T(reach);
    // sqrt(w) apart: the derivative of sqrt(w x) at w = 0 is 0 / 0, which made every residual of a
    // zero-weight ray's block NaN and failed the whole fit (issue 30, defect 5; t2 > 0 keeps this finite).
    const T scale = T(std::sqrt(weight)) * ceres::sqrt(t1 * t1 + t2 * t2);
    for (int k = 0; k < 3; ++k) residual[k] = scale * (T(d[k]) - e[k] / length);
    return true;
  }
};

}  // namespace

RayOnPlane ray_on_plane(const CausticRay& ray, const BundleAxis& axis, double ell, const Profile& profile) {
  RayOnPlane result;
  const glm::dvec3 q(ray.origin), d(ray.direction), a = axis.direction;
  const double along = glm::dot(d, a);
  if (!(along > 1e-12)) return result;
  const double travel = (glm::dot(axis.origin - q, a) + ell) / along;
  const glm::dvec3 c = axis.origin + ell * a;
  result.p = q + travel * d;
  const glm::dvec3 from = result.p - c;
  result.r = glm::length(from);
  result.t1 = std::fabs(travel);
  const glm::dvec3 e = glm::normalize(a - profile.g(result.r) * from);
  result.chord = glm::length(d - e);
  result.valid = true;
  return result;
}

Fit fit_spot_light(const std::vector<CausticRay>& rays, const std::vector<uint32_t>& members, const BundleAxis& axis,
                   const FitSettings& settings) {
  Fit fit;
  const glm::dvec3 a = axis.direction;
  // The rays the objective sums over: an even stride through the bundle.
  std::vector<uint32_t> used;
  const size_t stride = std::max<size_t>(1, (members.size() + settings.max_rays - 1) / std::max(1, settings.max_rays));
  // Rays that carry no energy add nothing to Eq. 5 (min_energy 0 keeps branches of vanishing energy).
  for (size_t i = 0; i < members.size(); i += stride)
    if (rays[members[i]].weight > 0.0f) used.push_back(members[i]);
  fit.rays_used = static_cast<int>(used.size());
  if (used.empty()) return fit;
  // The light plane starts behind the ray origins: behind all but the rearmost tenth of the bundle's
  // energy, so that a few rays leaving the object far back (after an internal reflection) do not push
  // it behind the whole object, where the other rays, traced back, would spread far out.
  std::vector<std::pair<double, double>> heights;  // (height of the origin along the axis, energy)
  double total_weight = 0.0, member_weight = 0.0;
  for (uint32_t index : members) {
    heights.emplace_back(glm::dot(glm::dvec3(rays[index].origin) - axis.origin, a), rays[index].weight);
    member_weight += rays[index].weight;
  }
  std::sort(heights.begin(), heights.end());
  double rearmost = heights.front().first, accumulated = 0.0;
  for (const auto& [height, weight] : heights) {
    accumulated += weight;
    rearmost = height;
    if (accumulated >= 0.1 * member_weight) break;
  }
  for (uint32_t index : used) total_weight += rays[index].weight;
  // First guess for a plane at l: where each ray's line comes nearest the axis, f, against its radius
  // on the plane: 1 / f = kappa + kappa beta r, a weighted line fit.
  auto first_guess = [&](double ell, double& kappa, double& beta) {
    double sw = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    const glm::dvec3 c = axis.origin + ell * a;
    for (uint32_t index : used) {
      const CausticRay& ray = rays[index];
      const RayOnPlane on = ray_on_plane(ray, axis, ell, Profile{});
      if (!on.valid || !(on.r > 0.0)) continue;
      const glm::dvec3 d(ray.direction), radial = (on.p - c) / on.r;
      // The ray's slope towards the axis per unit height is 1 / f(r) = -(d . radial) / (r (d . a)).
      const double inverse_f = -glm::dot(d, radial) / (on.r * glm::dot(d, a));
      const double w = ray.weight;
      sw += w;
      sx += w * on.r;
      sy += w * inverse_f;
      sxx += w * on.r * on.r;
      sxy += w * on.r * inverse_f;
    }
    kappa = beta = 0.0;
    if (!(sw > 0.0)) return;
    const double denominator = sw * sxx - sx * sx;
    const double slope = std::fabs(denominator) > 1e-300 ? (sw * sxy - sx * sy) / denominator : 0.0;
    kappa = (sy - slope * sx) / sw;
    beta = kappa != 0.0 ? std::max(0.0, slope / kappa) : 0.0;
    if (!std::isfinite(kappa)) kappa = 0.0;
    if (!std::isfinite(beta)) beta = 0.0;
  };
  // Eq. 5 over the rays used, normalised by their energy as the residuals are.
  auto objective = [&](double kappa, double beta, double ell) {
    double sum = 0.0;
    for (uint32_t index : used) {
      const RayOnPlane on = ray_on_plane(rays[index], axis, ell, Profile{kappa, beta});
      if (!on.valid) continue;
      const double t2 = on.t1 + settings.reach;
      sum += rays[index].weight / total_weight * (on.t1 * on.t1 + t2 * t2) * on.chord * on.chord;
    }
    return sum;
  };
  // Eq. 5 is not convex in l (a plane near the exit points can fold the bundle, rays from two radii
  // crossing it at one): the first guess is the best of planes spaced over the allowed range.
  double kappa = 0.0, beta = 0.0, ell = rearmost, best = std::numeric_limits<double>::infinity();
  const int starts = 9;
  for (int k = 0; k < starts; ++k) {
    const double candidate = rearmost - settings.plane_range * k / (starts - 1);
    double candidate_kappa, candidate_beta;
    first_guess(candidate, candidate_kappa, candidate_beta);
    const double cost = objective(candidate_kappa, candidate_beta, candidate);
    if (cost < best) {
      best = cost;
      kappa = candidate_kappa;
      beta = candidate_beta;
      ell = candidate;
    }
  }
  double parameters[3] = {kappa, beta, ell};
  ceres::Problem problem;
  for (uint32_t index : used) {
    const CausticRay& ray = rays[index];
    auto* cost = new ceres::AutoDiffCostFunction<RayResidual, 3, 1, 1, 1>(new RayResidual{
        glm::dvec3(ray.origin), glm::dvec3(ray.direction), axis.origin, a, settings.reach, ray.weight / total_weight});
    problem.AddResidualBlock(cost, nullptr, &parameters[0], &parameters[1], &parameters[2]);
  }
  problem.SetParameterLowerBound(&parameters[1], 0, 0.0);
  problem.SetParameterUpperBound(&parameters[2], 0, rearmost);
  problem.SetParameterLowerBound(&parameters[2], 0, rearmost - settings.plane_range);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = settings.max_iterations;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  // Ceres reports a failed evaluation through glog whatever logging_type says: the failure is detected
  // from the summary below and recorded, and the log stays out of the user's terminal.
  static std::once_flag quiet;
  std::call_once(quiet, [] { FLAGS_minloglevel = google::GLOG_FATAL; });
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    // The parameters are not trusted: the first guess stands, and the record says so.
    fit.failed = true;
    parameters[0] = kappa;
    parameters[1] = beta;
    parameters[2] = ell;
  }
  // Eq. 5 proper is twice Ceres's cost (Ceres minimises half the sum of squares).
  fit.initial_cost = 2.0 * summary.initial_cost;
  fit.final_cost = 2.0 * summary.final_cost;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.profile = Profile{parameters[0], parameters[1]};
  fit.ell = parameters[2];
  fit.origin = axis.origin + fit.ell * a;
  return fit;
}

}  // namespace causticbench::csl
