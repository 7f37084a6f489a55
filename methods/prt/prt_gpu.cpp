// prt's Vulkan backend on the method's side: the frame data the device takes (frame_data.h), filled from
// the build and the last update; the matrices uploaded once a build; the product in update() and the
// lookup in render() (vulkan_prt.h); `--dump-frame`. The lighting is the CPU's projection for both.
#include <cstring>

#include "methods/common/gpu_arrays.h"
#include "methods/common/harmonic_lighting.h"
#include "methods/prt/frame_data.h"
#include "methods/prt/prt.h"
#include "methods/prt/vulkan_prt.h"

namespace causticbench {

struct PrtMethod::GpuState {
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<VulkanPrt> vulkan;
  PrtFrameData frame;
  uint64_t build_uploaded = 0;  // builds_ when the matrices went up (0: never)
  double product_ms = 0.0, lookup_ms = 0.0;
  bool last_render = false;     // the last render ran on the device
};

PrtMethod::PrtMethod() = default;
PrtMethod::~PrtMethod() = default;

void PrtMethod::fill_frame_data(PrtFrameData& frame, bool with_matrices) const {
  using namespace prt_record;
  frame.bands = static_cast<uint32_t>(settings_.bands);
  frame.precision = settings_.half ? 1u : 0u;
  const uint32_t n2 = frame.coefficients();
  frame.objects.assign(objects_.size() * kWords, 0u);
  frame.lighting.clear();
  if (with_matrices) frame.matrices.clear();
  uint64_t elements = 0, incident = 0;
  for (size_t i = 0; i < objects_.size(); ++i) {
    const ObjectTransfer& transfer = objects_[i];
    uint32_t* record = frame.objects.data() + i * kWords;
    auto put_float = [&](uint32_t at, float value) { std::memcpy(record + at, &value, sizeof(float)); };
    for (int column = 0; column < 3; ++column)
      for (int row = 0; row < 3; ++row) {
        put_float(kLinear + 3 * column + row, transfer.map.linear[column][row]);
        put_float(kNormals + 3 * column + row, transfer.map.normals[column][row]);
      }
    const GridLayout& grid = *transfer.field.grid;
    for (int axis = 0; axis < 3; ++axis) {
      put_float(kOffset + axis, transfer.map.offset[axis]);
      put_float(kCenter + axis, grid.center()[axis]);
    }
    put_float(kHalf, grid.radius());
    record[kResolution] = static_cast<uint32_t>(grid.resolution());
    put_float(kCell, grid.cell_size());
    record[kMatrices] = static_cast<uint32_t>(elements);
    record[kLighting] = static_cast<uint32_t>(i * 3 * n2);
    record[kIncident] = static_cast<uint32_t>(incident);
    frame.lighting.insert(frame.lighting.end(), transfer.lighting.begin(), transfer.lighting.end());
    const uint64_t entries = grid.points() * transfer.field.values_per_cell();
    if (with_matrices) {
      if (!settings_.half) {
        const size_t first = frame.matrices.size();
        frame.matrices.resize(first + entries);
        std::memcpy(frame.matrices.data() + first, transfer.field.matrices.data(), entries * sizeof(float));
      } else {
        // Two halves a word, the lower first; an object's first entry may share the previous object's
        // last word (its element index says which half).
        frame.matrices.resize((elements + entries + 1) / 2, 0u);
        for (uint64_t e = 0; e < entries; ++e) {
          const uint64_t element = elements + e;
          frame.matrices[element / 2] |= uint32_t(transfer.field.halves[e]) << (16 * (element % 2));
        }
      }
    }
    elements += entries;
    incident += grid.points() * 3 * n2;
  }
  frame.basis_factors = basis_factors(settings_.bands);
  frame.clamped_cosines.clear();
  for (int l = 0; l < settings_.bands; ++l) frame.clamped_cosines.push_back(static_cast<float>(clamped_cosine(l)));
}

void PrtMethod::update_on_device() {
  if (!gpu_) {
    gpu_ = std::make_unique<GpuState>();
    gpu_->context = std::make_unique<gpu::Context>();
    gpu_->vulkan = std::make_unique<VulkanPrt>(*gpu_->context);
  }
  const bool upload = gpu_->build_uploaded != builds_;
  fill_frame_data(gpu_->frame, upload);
  if (upload) {
    check_prt_frame_data(gpu_->frame, "prt's Vulkan backend");
    gpu_->vulkan->upload_build(gpu_->frame);
    std::vector<uint32_t>().swap(gpu_->frame.matrices);  // on the device now
    gpu_->build_uploaded = builds_;
  }
  gpu_->product_ms = gpu_->vulkan->update(gpu_->frame);
}

Image PrtMethod::render_on_device(const GBuffer& gbuffer) {
  PrtFrameData& frame = gpu_->frame;
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  const std::vector<float> rgba = gpu_->vulkan->lookup(frame, gpu_->lookup_ms);
  // As the CPU counts: every receiver point once per object.
  size_t receivers = 0;
  for (uint8_t receiver : gbuffer.receiver) receivers += receiver ? 1 : 0;
  points_evaluated_ = static_cast<double>(receivers * objects_.size());
  gpu_->last_render = true;
  return image_of_rgba(gbuffer.width, gbuffer.height, rgba);
}

std::optional<double> PrtMethod::gpu_render_milliseconds() const {
  if (!gpu_ || !device_frame_ || !gpu_->last_render) return std::nullopt;
  return gpu_->product_ms + gpu_->lookup_ms;
}

void PrtMethod::dump_frame(const GBuffer& gbuffer, const ParamSet&, const Image& output, const std::string& folder) const {
  PrtFrameData frame;
  fill_frame_data(frame, true);
  frame.width = static_cast<uint32_t>(gbuffer.width);
  frame.height = static_cast<uint32_t>(gbuffer.height);
  fill_receiver_arrays(gbuffer, frame.receiver_positions, frame.receiver_normals);
  check_prt_frame_data(frame, folder);
  // First, so that a folder that held another method's dump names prt before its files land.
  write_dump_method(folder, "prt");
  write_prt_frame_data(frame, folder);
  write_dump_irradiance(folder, device_frame_ ? "vulkan" : "cpu", output);
}

}  // namespace causticbench
