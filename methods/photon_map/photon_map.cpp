// photon_map's lifecycle (trace, index, build cache) and its per-pixel estimate; its knobs are in
// photon_map_info.cpp.
#include "methods/photon_map/photon_map.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nanoflann.hpp>

#include "core/files.h"
#include "core/parallel.h"
#include "core/scene_description.h"
#include "methods/common/photon_memory.h"
#include "methods/common/photon_view.h"

namespace causticbench {

// nanoflann's view of the photon positions.
struct PhotonCloud {
  const std::vector<Photon>* photons = nullptr;
  size_t kdtree_get_point_count() const { return photons->size(); }
  float kdtree_get_pt(size_t index, size_t dimension) const { return (*photons)[index].position[dimension]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

using PhotonTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PhotonCloud>, PhotonCloud, 3>;

struct PhotonMapMethod::Index {
  PhotonCloud cloud;
  std::unique_ptr<PhotonTree> tree;
};

PhotonMapMethod::PhotonMapMethod() = default;
PhotonMapMethod::~PhotonMapMethod() = default;

// The trace's peak holds every deposited photon twice (methods/common/photon_memory.h); an animated
// scene retraces each frame while the previous frame's kd-tree (a 4-byte index and about 10 bytes of
// nodes a photon) is still alive.
std::vector<MemoryTerm> PhotonMapMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double photons = static_cast<double>(knobs.integer("photons"));
  const double deposits = deposits_per_photon_bound(context, static_cast<uint64_t>(knobs.integer("seed")),
                                                    PhotonTracerSettings{}.max_bounces);
  const double per_photon = kBytesPerTracedPhoton + (scene_is_static(context.scene) ? 0.0 : 14.0);
  return {MemoryTerm{{"photons"}, photons * deposits * per_photon,
                     fmt::format("{:.3g} photons x {:.2f} deposited each at most x {:.0f} bytes", photons, deposits,
                                 per_photon)}};
}

void PhotonMapMethod::prepare(const PrepareContext& context, const ParamSet& build) {
  build_ = build;
  photons_.clear();
  stats_ = PhotonStats{};
  index_.reset();
  static_scene_ = scene_is_static(context.scene);
  if (static_scene_) trace(context.tracer);
}

void PhotonMapMethod::update(const FrameContext& frame, const ParamSet& frame_knobs) {
  if (!static_scene_) trace(frame.tracer);
}

void PhotonMapMethod::trace(const Tracer& tracer) {
  photons_.clear();
  stats_ = PhotonStats{};
  CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{static_cast<uint64_t>(build_.integer("seed"))});
  photon_tracer.trace(0, static_cast<uint64_t>(build_.integer("photons")), photons_, stats_);
  build_index();
}

void PhotonMapMethod::build_index() {
  index_ = std::make_unique<Index>();
  index_->cloud.photons = &photons_;
  index_->tree = std::make_unique<PhotonTree>(3, index_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  index_->tree->buildIndex();
}

// A static scene's photons depend on everything that shapes a photon path (every object, every light)
// and on the build knobs; not on the camera.
std::optional<nlohmann::json> PhotonMapMethod::build_dependencies(const PrepareContext& context,
                                                                  const ParamSet& build) const {
  if (!scene_is_static(context.scene)) return std::nullopt;
  return nlohmann::json{{"scene", scene_content_json(context.scene)}, {"build", build.to_json()}};
}

// photons.bin: the photons and their statistics; kdtree.bin: nanoflann's index over them (building it
// costs more than tracing the photons, so it is part of the build). The build cache checks both files'
// checksums before load_build() reads them (nanoflann trusts its input).
void PhotonMapMethod::save_build(const std::string& folder) const {
  // Through the store's atomic writes: a full disk is a WriteError naming the file and ENOSPC, which stops
  // the run and leaves it pending (issue 30, defect 6), not a run stored as failed.
  write_stream_atomically((std::filesystem::path(folder) / "photons.bin").string(), [&](std::ostream& stream) {
    const uint64_t header[4] = {photons_.size(), stats_.emitted, stats_.deposited, stats_.rays};
    stream.write(reinterpret_cast<const char*>(header), sizeof(header));
    stream.write(reinterpret_cast<const char*>(photons_.data()), static_cast<std::streamsize>(photons_.size() * sizeof(Photon)));
  });
  if (photons_.empty()) return;  // no caustic photon (nothing in view or nothing aimed at): no tree to store
  write_stream_atomically((std::filesystem::path(folder) / "kdtree.bin").string(),
                          [&](std::ostream& stream) { index_->tree->saveIndex(stream); });
}

void PhotonMapMethod::load_build(const PrepareContext& context, const ParamSet& build, const std::string& folder) {
  build_ = build;
  static_scene_ = true;
  std::string path = (std::filesystem::path(folder) / "photons.bin").string();
  std::ifstream stream(path, std::ios::binary);
  uint64_t header[4] = {};
  stream.read(reinterpret_cast<char*>(header), sizeof(header));
  if (!stream || std::filesystem::file_size(path) != sizeof(header) + header[0] * sizeof(Photon)) {
    throw std::runtime_error(path + ": truncated or not a photon file");
  }
  photons_.resize(header[0]);
  stream.read(reinterpret_cast<char*>(photons_.data()), static_cast<std::streamsize>(photons_.size() * sizeof(Photon)));
  stats_ = PhotonStats{header[1], header[2], header[3]};
  if (photons_.empty()) {
    index_.reset();  // render() returns zeros without looking at the index
    return;
  }
  std::ifstream tree(std::filesystem::path(folder) / "kdtree.bin", std::ios::binary);
  if (!tree) throw std::runtime_error(folder + "/kdtree.bin: not found");
  index_ = std::make_unique<Index>();
  index_->cloud.photons = &photons_;
  index_->tree = std::make_unique<PhotonTree>(3, index_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  index_->tree->loadIndex(tree);
  if (!tree) throw std::runtime_error(folder + "/kdtree.bin: truncated");
}

nlohmann::json PhotonMapMethod::record() const {
  nlohmann::json record = {
      {"photons_traced", static_scene_ ? "once, in prepare (static scene)" : "every frame, in update"}};
  if (auto_radius_) {
    const auto [median, least, largest] = *auto_radius_;
    record["max_radius_used"] = {{"median", median}, {"least", least}, {"largest", largest}};
    record["max_radius_why"] = fmt::format(
        "auto: {:g} times each receiver pixel's footprint on its surface (median {:.3g}, from {:.3g} to {:.3g} scene "
        "units): a dim region blurs over at most that many pixels, and every photon in view lies within the cap "
        "of a pixel's point",
        kAutoRadiusFootprints, median, least, largest);
  }
  return record;
}

namespace {

// The gather radius's cap at a pixel: max_radius in scene units, or under `auto` a multiple of the
// pixel's footprint on its surface. A cap in scene units is right only for the scene it was chosen for:
// 0.1 is 6 to 8 footprints on the shipped scenes at 256 x 256, but below one footprint on a 12 m table
// at 96 x 96, where it turned the image into discs around the pixel points and lost 76 % of the light.
// The footprint follows the image instead: at most 8 pixels of blur in a dim region, whatever the units.
struct RadiusCap {
  bool automatic;
  float fixed;
  explicit RadiusCap(const ParamSet& params)
      : automatic(params.is_auto("max_radius")),
        fixed(automatic ? 0.0f : static_cast<float>(params.real("max_radius"))) {}
  float at(const GBuffer& gbuffer, size_t pixel) const {
    return automatic ? static_cast<float>(PhotonMapMethod::kAutoRadiusFootprints) * gbuffer.footprint[pixel] : fixed;
  }
  // Median, least and largest cap over the receiver pixels, for the record.
  std::array<double, 3> summary(const GBuffer& gbuffer) const {
    std::vector<float> caps;
    for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel)
      if (gbuffer.receiver[pixel]) caps.push_back(at(gbuffer, pixel));
    if (caps.empty()) return {0.0, 0.0, 0.0};
    std::nth_element(caps.begin(), caps.begin() + caps.size() / 2, caps.end());
    const double median = caps[caps.size() / 2];
    const auto [least, largest] = std::minmax_element(caps.begin(), caps.end());
    return {median, *least, *largest};
  }
};

}  // namespace

Image PhotonMapMethod::render(const GBuffer& gbuffer, const ParamSet& params) {
  Image result(gbuffer.width, gbuffer.height, 3);
  if (photons_.empty()) return result;
  const size_t k = std::min<size_t>(static_cast<size_t>(params.integer("k")), photons_.size());
  const RadiusCap cap(params);
  const float cone = static_cast<float>(params.real("cone_filter_k"));
  const double emitted = static_cast<double>(stats_.emitted);
  // Normalisation of the cone filter over a disc: integral of (1 - d / (k r)) = (1 - 2 / (3 k)) pi r^2.
  const double normalisation = 1.0 - 2.0 / (3.0 * cone);
  parallel_blocks(gbuffer.pixel_count(), 256, [&](size_t begin, size_t end, size_t) {
    std::vector<uint32_t> indices(k);
    std::vector<float> distances2(k);
    for (size_t pixel = begin; pixel < end; ++pixel) {
      if (!gbuffer.receiver[pixel]) continue;
      const Vec3 point = gbuffer.position[pixel], normal = gbuffer.normal[pixel];
      size_t found = index_->tree->knnSearch(&point.x, k, indices.data(), distances2.data());
      if (found == 0) continue;
      float radius = std::min(cap.at(gbuffer, pixel), std::sqrt(distances2[found - 1]));
      if (radius <= 0.0f) continue;
      glm::dvec3 sum(0.0);
      for (size_t j = 0; j < found; ++j) {
        float distance = std::sqrt(distances2[j]);
        if (distance > radius) break;
        const Photon& photon = photons_[indices[j]];
        if (glm::dot(photon.normal, normal) < 0.7f) continue;
        sum += glm::dvec3(photon.power) * static_cast<double>(1.0f - distance / (cone * radius));
      }
      double area = kPiDouble * static_cast<double>(radius) * radius * normalisation;
      result.set_rgb(pixel, Color(sum / (area * emitted)));
    }
  });
  return result;
}

namespace {

// The receiver pixels' points, for a nearest-point search.
struct PixelCloud {
  std::vector<Vec3> points;
  size_t kdtree_get_point_count() const { return points.size(); }
  float kdtree_get_pt(size_t i, size_t axis) const { return points[i][static_cast<int>(axis)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using PixelTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PixelCloud>, PixelCloud, 3>;

}  // namespace

// The flux of the photons the camera sees on receiver pixels (methods/common/photon_view.h) that lie
// farther than the cap from every receiver pixel's point: light no gather can count, whatever k. (A
// photon between pixel points that a small k leaves out is not lost: each pixel's estimate stays a
// consistent density estimate, the photon is only work that did not help. The cap is what can hide
// light: max_radius below the pixel spacing, as in a scene measured in other units than the value
// assumes, leaves the image a speckle of discs around the pixel points.) Under `auto` each pixel has
// its own cap; a photon counts as reached when one of its kNeighbours nearest pixel points holds it in
// that point's cap (a farther point with a cap large enough to reach it would have a footprint many
// times the spacing of the nearer ones; the count is exact for a fixed cap).
std::optional<LostFlux> PhotonMapMethod::lost_flux(const FrameContext& frame, const GBuffer& gbuffer,
                                                   const ParamSet& params) {
  const RadiusCap cap(params);
  // The caps the record states, summarised here, outside the timed render.
  auto_radius_ = cap.automatic ? std::optional(cap.summary(gbuffer)) : std::nullopt;
  LostFlux lost;
  lost.what = "flux of the photons in view farther than max_radius from every receiver pixel's point";
  lost.knob = "max_radius";
  lost.advice = cap.automatic ? "set max_radius to a value in scene units above the receivers' pixel spacing"
                              : fmt::format("raise max_radius (now {:g}) to at least the receivers' pixel spacing, "
                                            "or set it to auto (8 pixel footprints)",
                                            cap.fixed);
  PixelCloud cloud;
  std::vector<float> caps;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    cloud.points.push_back(gbuffer.position[pixel]);
    caps.push_back(cap.at(gbuffer, pixel));
  }
  if (photons_.empty() || cloud.points.empty()) return lost;
  PixelTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  // Per photon, its flux when in view, and whether it lies beyond the cap: summed in photon order after,
  // so the same for any thread count.
  std::vector<double> seen(photons_.size(), 0.0);
  std::vector<uint8_t> beyond(photons_.size(), 0);
  parallel_blocks(photons_.size(), 2048, [&](size_t begin, size_t end, size_t) {
    for (size_t i = begin; i < end; ++i) {
      const Photon& photon = photons_[i];
      // The receiver mask before the shadow ray, as the reference's tally does.
      std::optional<CameraFrame::ImagePoint> image = frame.frame.camera.project(photon.position, photon.normal);
      if (!image || !gbuffer.receiver[static_cast<size_t>(image->y) * gbuffer.width + image->x] ||
          !camera_sees(*image, frame.tracer, photon))
        continue;
      seen[i] = luminance(photon.power);
      constexpr size_t kNeighbours = 8;
      uint32_t nearest[kNeighbours] = {};
      float distance2[kNeighbours] = {};
      const size_t found = tree.knnSearch(&photon.position.x, cap.automatic ? kNeighbours : 1, nearest, distance2);
      bool reached = false;
      for (size_t j = 0; j < found && !reached; ++j)
        reached = std::sqrt(static_cast<double>(distance2[j])) <= caps[nearest[j]];
      beyond[i] = !reached;
    }
  });
  double total = 0.0, missed = 0.0;
  for (size_t i = 0; i < photons_.size(); ++i) {
    total += seen[i];
    if (beyond[i]) missed += seen[i];
  }
  lost.fraction = total > 0.0 ? missed / total : 0.0;
  return lost;
}

size_t PhotonMapMethod::memory_bytes() const {
  size_t tree = index_ && index_->tree ? index_->tree->usedMemory(*index_->tree) : 0;
  return photons_.size() * sizeof(Photon) + tree;
}

Counters PhotonMapMethod::counters() const {
  return {{"photons_emitted", static_cast<double>(stats_.emitted)},
          {"photons_stored", static_cast<double>(photons_.size())}};
}

}  // namespace causticbench
