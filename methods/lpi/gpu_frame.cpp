#include "methods/lpi/gpu_frame.h"

#include <cstring>

#include <fmt/format.h>

#include "core/errors.h"
#include "methods/common/gpu_arrays.h"

namespace causticbench::lpi {

namespace {

uint32_t bits(float value) {
  uint32_t word;
  std::memcpy(&word, &value, sizeof(word));
  return word;
}

void put_vector(uint32_t* record, uint32_t at, const Vec3& v) {
  for (int k = 0; k < 3; ++k) record[at + k] = bits(v[k]);
}

void put_matrix(uint32_t* record, uint32_t at, const glm::mat3& m) {
  for (int column = 0; column < 3; ++column) put_vector(record, at + 3 * column, m[column]);
}

uint32_t word_count(size_t words) {
  if (words > UINT32_MAX) throw InputError(fmt::format("lpi backend vulkan: {} words of stored values exceed 2^32", words));
  return static_cast<uint32_t>(words);
}

// The shells' radii and geodesic lookup table, appended to `shells`; the record says where.
void append_shells(const ShellLayout& layout, uint32_t* record, std::vector<uint32_t>& shells) {
  using namespace lpi_record;
  const SphericalMesh& mesh = layout.mesh();
  record[kRadii] = word_count(shells.size());
  for (float radius : layout.radii()) shells.push_back(bits(radius));
  record[kTriangles] = word_count(shells.size());
  for (const auto& triangle : mesh.triangles()) {
    for (uint32_t point : triangle) {
      const Vec3& p = mesh.points()[point];
      for (int k = 0; k < 3; ++k) shells.push_back(bits(p[k]));
    }
    for (uint32_t point : triangle) shells.push_back(point);
  }
  record[kTexels] = word_count(shells.size());
  for (const SphericalMesh::Texel& texel : mesh.table_texels()) {
    shells.push_back(texel.first);
    shells.push_back(texel.rest);
  }
  record[kCandidates] = word_count(shells.size());
  shells.insert(shells.end(), mesh.table_candidates().begin(), mesh.table_candidates().end());
  record[kTableSize] = static_cast<uint32_t>(mesh.table_resolution());
  record[kLongestEdge] = bits(static_cast<float>(mesh.longest_edge()));
}

}  // namespace

void check_vulkan_supports(const VolumeSettings& settings, const std::string& what) {
  if (settings.storage == StorageKind::grid || settings.storage == StorageKind::shells) return;
  throw InputError(fmt::format(
      "lpi: {} needs the Vulkan kernel, which evaluates storage grid and shells (every blend, symmetry, orientation, "
      "precision and outside mode, any number of objects), not storage {}: use storage grid or shells{}",
      what, settings.storage == StorageKind::multires ? "multires" : "sh",
      what == "backend vulkan" ? ", or backend cpu" : ""));
}

void fill_volume_data(const VolumeSettings& settings, const std::vector<ObjectVolumes>& objects, LpiFrameData& frame) {
  using namespace lpi_record;
  frame.storage = settings.storage == StorageKind::grid ? 0 : 1;
  frame.channels = static_cast<uint32_t>(channel_count(settings.orientation));
  const bool signed_values = settings.orientation == Orientation::vector;
  frame.precision = settings.precision == Precision::float32   ? 0
                    : settings.precision == Precision::float16 ? 1
                                                               : (signed_values ? 3 : 2);
  frame.objects.assign(objects.size() * kWords, 0u);
  frame.values.clear();
  frame.scales.clear();
  frame.shells.clear();
  for (size_t i = 0; i < objects.size(); ++i) {
    const ObjectVolumes& object = objects[i];
    uint32_t* record = frame.objects.data() + i * kWords;
    put_vector(record, kCenter, object.layout->center());
    record[kRadius] = bits(object.layout->radius());
    // Each object's bytes from a word boundary, so that the kernel addresses them from its first word.
    record[kValues] = word_count(frame.values.size());
    const std::vector<uint8_t>& bytes = object.values.bytes();
    const size_t first = frame.values.size();
    frame.values.resize(first + (bytes.size() + 3) / 4, 0u);
    if (!bytes.empty()) std::memcpy(frame.values.data() + first, bytes.data(), bytes.size());
    record[kPoints] = static_cast<uint32_t>(object.values.points());
    record[kScales] = word_count(frame.scales.size());
    frame.scales.insert(frame.scales.end(), object.values.scales().begin(), object.values.scales().end());
    if (const auto* grid = dynamic_cast<const GridLayout*>(object.layout.get())) {
      record[kCount] = static_cast<uint32_t>(grid->resolution());
      record[kSpacing] = bits(grid->cell_size());
    } else {
      const auto& shells = static_cast<const ShellLayout&>(*object.layout);
      record[kCount] = static_cast<uint32_t>(shells.radii().size());
      record[kSpacing] = static_cast<uint32_t>(shells.directions());
      append_shells(shells, record, frame.shells);
    }
  }
}

void fill_frame_lights(const std::vector<ObjectFrame>& views, Outside outside, LpiFrameData& frame) {
  using namespace lpi_record;
  frame.outside = outside == Outside::clamp ? 0 : outside == Outside::fade ? 1 : 2;
  frame.lights.clear();
  for (size_t i = 0; i < views.size(); ++i) {
    uint32_t* record = frame.objects.data() + i * kWords;
    put_matrix(record, kLinear, views[i].map.linear);
    put_vector(record, kOffset, views[i].map.offset);
    put_matrix(record, kNormals, views[i].map.normals);
    record[kFirstLight] = static_cast<uint32_t>(frame.lights.size() / lpi_light::kFloats);
    record[kLightCount] = static_cast<uint32_t>(views[i].lights.size());
    for (const LightView& light : views[i].lights) {
      frame.lights.resize(frame.lights.size() + lpi_light::kFloats, 0.0f);
      float* out = frame.lights.data() + frame.lights.size() - lpi_light::kFloats;
      for (int c = 0; c < 3; ++c) out[c] = light.irradiance[c];
      out[3] = static_cast<float>(light.reads.count);
      for (int r = 0; r < light.reads.count; ++r) {
        const SampleRead& read = light.reads.reads[r];
        float* at = out + lpi_light::kFirstRead + r * lpi_light::kReadFloats;
        at[0] = static_cast<float>(read.sample);  // exact: light samples are far fewer than 2^24
        at[1] = read.weight;
        at[2] = read.rotated ? 1.0f : 0.0f;
        for (int column = 0; column < 3; ++column) {
          for (int row = 0; row < 3; ++row) at[3 + 3 * column + row] = read.rotation[column][row];
        }
      }
    }
  }
}

void fill_receivers(const GBuffer& gbuffer, LpiFrameData& frame) {
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
}

}  // namespace causticbench::lpi
