// prt's build: what determines it (build_dependencies), its files (save_build, load_build) and its
// memory at the peak (knob_memory).
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "core/files.h"
#include "core/scene_description.h"
#include "methods/common/ball_radius.h"
#include "methods/prt/prt.h"

namespace causticbench {

namespace {

const char* kMatricesFormat = "causticbench prt matrices 2";

}  // namespace

// Per specular object: its shape, material and scale at frame 0 (the build is in its own frame), and
// with auto the ball the probes chose; the build knobs. Not the lights: the transfer holds every
// direction.
std::optional<nlohmann::json> PrtMethod::build_dependencies(const PrepareContext& context, const ParamSet& build) const {
  const prt::TransferSettings settings = prt::transfer_settings(build);
  nlohmann::json objects = nlohmann::json::array();
  for (int object : context.rest.specular_objects()) {
    const SceneObject& source = context.scene.objects[object];
    const Scene alone = build_space_scene(context.scene, object);
    const SceneFrame frame(alone, 0.0);
    const glm::dvec3 scale = source.transform.scale.at(0.0);
    nlohmann::json entry = {{"shape", shape_json(source.shape)},
                            {"material", material_json(source.material)},
                            {"scale", {scale.x, scale.y, scale.z}}};
    if (build.is_auto("volume_radius"))
      entry["volume_radius"] =
          choose_ball_radius(context, object, frame.bounds[0], settings.volume_radius, settings.grid_resolution).radii;
    objects.push_back(std::move(entry));
  }
  return nlohmann::json{{"objects", objects}, {"build", build.key_json(static_info().params)}};
}

// The peak per object: the matrices (cells x 3 n^4 floats), and while shooting eight chunk sums of floats
// and one of doubles of the cells' incident coefficients (cells x 3 n^2 x (8 x 4 + 8) bytes).
std::vector<MemoryTerm> PrtMethod::knob_memory(const PrepareContext& context, const ParamSet& knobs) const {
  const double n = static_cast<double>(knobs.integer("sh_order"));
  const double cells = std::pow(static_cast<double>(knobs.integer("grid_resolution")), 3.0);
  // float16: the floats the build sums, and the halves beside them while they are converted.
  const bool half = knobs.has("precision") && knobs.text("precision") == "float16";
  const double matrices = cells * 3.0 * n * n * n * n * (half ? 6.0 : 4.0), shooting = cells * 3.0 * n * n * 40.0;
  std::vector<MemoryTerm> terms;
  for (int object : context.rest.specular_objects())
    terms.push_back(MemoryTerm{{"grid_resolution", "sh_order"}, matrices + shooting,
                               fmt::format("object '{}': {:.0f} cells x 3 x {:g}^4 floats ({:.0f} MiB) + {:.0f} MiB while "
                                           "shooting",
                                           context.scene.objects[object].name, cells, n, matrices / 1048576.0,
                                           shooting / 1048576.0)});
  return terms;
}

// One file per object: a header line, the counts (bands, entries, bytes an entry), then the entries.
void PrtMethod::save_build(const std::string& folder) const {
  nlohmann::json meta = nlohmann::json::array();
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectTransfer& transfer = objects_[i];
    const std::string name = fmt::format("object_{}.bin", i);
    write_stream_atomically((std::filesystem::path(folder) / name).string(), [&](std::ostream& stream) {
      const bool half = transfer.field.matrices.empty();
      const uint64_t header[3] = {static_cast<uint64_t>(transfer.field.bands), transfer.field.stored_values(),
                                  half ? sizeof(uint16_t) : sizeof(float)};
      stream.write(kMatricesFormat, static_cast<std::streamsize>(std::strlen(kMatricesFormat) + 1));
      stream.write(reinterpret_cast<const char*>(header), sizeof(header));
      if (half)
        stream.write(reinterpret_cast<const char*>(transfer.field.halves.data()),
                     static_cast<std::streamsize>(transfer.field.halves.size() * sizeof(uint16_t)));
      else
        stream.write(reinterpret_cast<const char*>(transfer.field.matrices.data()),
                     static_cast<std::streamsize>(transfer.field.matrices.size() * sizeof(float)));
    });
    meta.push_back({{"file", name},
                    {"object", transfer.name},
                    {"precompute_seconds", transfer.field.shoot_seconds},
                    {"emitted", transfer.field.stats.emitted},
                    {"deposited", transfer.field.stats.deposited},
                    {"rays", transfer.field.stats.rays},
                    {"direction_response", transfer.field.direction_response}});
  }
  write_text_atomically((std::filesystem::path(folder) / "transfer.json").string(), meta.dump(2) + "\n");
}

void PrtMethod::load_build(const PrepareContext& context, const ParamSet& build, const std::string& folder) {
  plan(context, build);
  std::ifstream meta_stream(std::filesystem::path(folder) / "transfer.json");
  const nlohmann::json meta = nlohmann::json::parse(meta_stream, nullptr, false);
  if (meta.is_discarded() || !meta.is_array() || meta.size() != objects_.size())
    throw std::runtime_error(folder + "/transfer.json: unreadable or not one entry per specular object");
  for (size_t i = 0; i < objects_.size(); ++i) {
    ObjectTransfer& transfer = objects_[i];
    const std::string path = (std::filesystem::path(folder) / fmt::format("object_{}.bin", i)).string();
    std::ifstream stream(path, std::ios::binary);
    std::string format(std::strlen(kMatricesFormat) + 1, '\0');
    stream.read(format.data(), static_cast<std::streamsize>(format.size()));
    uint64_t header[3] = {};
    stream.read(reinterpret_cast<char*>(header), sizeof(header));
    const uint64_t expected = transfer.field.grid->points() * transfer.field.values_per_cell();
    const uint64_t entry = settings_.half ? sizeof(uint16_t) : sizeof(float);
    if (!stream || format != std::string(kMatricesFormat, format.size()) ||
        header[0] != static_cast<uint64_t>(settings_.bands) || header[1] != expected || header[2] != entry)
      throw std::runtime_error(path + ": not the matrices of this build");
    if (settings_.half) {
      transfer.field.halves.resize(expected);
      stream.read(reinterpret_cast<char*>(transfer.field.halves.data()), static_cast<std::streamsize>(expected * entry));
    } else {
      transfer.field.matrices.resize(expected);
      stream.read(reinterpret_cast<char*>(transfer.field.matrices.data()), static_cast<std::streamsize>(expected * entry));
    }
    if (!stream) throw std::runtime_error(path + ": truncated");
    transfer.field.shoot_seconds = meta[i].value("precompute_seconds", 0.0);
    transfer.field.stats = PhotonStats{meta[i].value("emitted", uint64_t{0}), meta[i].value("deposited", uint64_t{0}),
                                       meta[i].value("rays", uint64_t{0})};
    // Stored since the band limit's loss is measured; a build from before has none (reported unknown).
    transfer.field.direction_response = meta[i].value("direction_response", std::vector<double>{});
    if (transfer.field.direction_response.size() == 3 * static_cast<size_t>(settings_.source_directions))
      transfer.response = prt::response_harmonics(transfer.field.direction_response);
  }
  ++builds_;
}

}  // namespace causticbench
