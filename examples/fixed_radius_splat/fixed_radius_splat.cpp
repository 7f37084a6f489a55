// fixed_radius_splat: caustic photons traced every frame and gathered within a fixed world-space radius,
// the simplest density estimate (Jensen 1996's photon map without the k nearest neighbours). A small
// but real method, built outside causticbench's tree against its installed SDK and loaded as a plugin
// (docs/sdk.md): `causticbench --plugin fixed_radius_splat.so run experiment.yaml`.
//
// E_c at a receiver point x with normal n is the power of the photons within `radius` of x that arrived
// on the side n faces, divided by the disc's area and the photons emitted: an unbiased estimate of the
// irradiance averaged over the disc, blurred by the radius and noisy in inverse proportion to it.
#include <algorithm>
#include <vector>

#include "core/parallel.h"
#include "core/photon_tracer.h"
#include "methods/common/photon_grid.h"
#include "methods/method.h"
#include "methods/plugin.h"

namespace splat_example {

using namespace causticbench;

class FixedRadiusSplat : public CausticMethod {
 public:
  static const MethodInfo& static_info() {
    static const MethodInfo info = [] {
      MethodInfo m;
      m.name = "fixed_radius_splat";
      m.paper = "the fixed-radius density estimate (Jensen 1996, without the k nearest); an out-of-tree example";
      m.summary = "Traces caustic photons every frame and divides the flux within a fixed radius by the disc's area.";
      m.params = {
          ParamSpec::integer("photons", 200000, 1000, 1e8, "photons traced per frame", ParamPhase::frame),
          ParamSpec::integer("seed", 1, 0, 4e9, "seed of the photon tracer", ParamPhase::frame),
          ParamSpec::real("radius", 0.05, 1e-4, 10.0, "gather radius in metres", ParamPhase::render),
      };
      Capabilities& c = m.capabilities;
      c.reflection = c.refraction = c.multiple_bounces = true;
      c.directional_light = c.point_light = c.environment_light = true;
      c.moving_light = c.moving_objects = c.occlusion = c.non_lambertian_receivers = true;
      c.notes = {{"non_lambertian_receivers", "E_c is irradiance, independent of the receiver's BRDF"}};
      m.quick_knobs = {"photons=20000", "radius=0.1"};
      m.budget_knob = "photons";
      m.counters = {counter_quantity("photons_emitted", "photons", "photons emitted toward the specular objects"),
                    counter_quantity("photons_stored", "photons", "caustic photons deposited this frame")};
      return m;
    }();
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  void prepare(const PrepareContext& context, const ParamSet& build) override {}

  void update(const FrameContext& frame, const ParamSet& frame_knobs) override {
    photons_.clear();
    stats_ = PhotonStats{};
    CausticPhotonTracer tracer(frame.tracer, PhotonTracerSettings{static_cast<uint64_t>(frame_knobs.integer("seed"))});
    tracer.trace(0, static_cast<uint64_t>(frame_knobs.integer("photons")), photons_, stats_);
  }

  Image render(const GBuffer& gbuffer, const ParamSet& render) override {
    const float radius = static_cast<float>(render.real("radius"));
    const double scale = 1.0 / (kPiDouble * radius * radius * static_cast<double>(std::max<uint64_t>(1, stats_.emitted)));
    Image image(gbuffer.width, gbuffer.height, 3);
    if (photons_.empty()) return image;
    const PhotonGrid grid(photons_, radius);
    // Fixed blocks of pixels: the same output for any thread count.
    parallel_blocks(gbuffer.pixel_count(), 1024, [&](size_t begin, size_t end, size_t) {
      for (size_t pixel = begin; pixel < end; ++pixel) {
        if (!gbuffer.receiver[pixel]) continue;
        const Vec3 point = gbuffer.position[pixel], normal = gbuffer.normal[pixel];
        glm::dvec3 flux(0.0);
        grid.for_each_near(point, radius, [&](const Photon& photon) {
          const Vec3 offset = photon.position - point;
          // Inside the disc, on the side of the surface the camera sees.
          if (glm::dot(offset, offset) < radius * radius && glm::dot(photon.normal, normal) > 0.7f)
            flux += glm::dvec3(photon.power);
        });
        image.set_rgb(pixel, Color(flux * scale));
      }
    });
    return image;
  }

  size_t memory_bytes() const override { return photons_.size() * sizeof(Photon); }
  Counters counters() const override {
    return {{"photons_emitted", static_cast<double>(stats_.emitted)},
            {"photons_stored", static_cast<double>(photons_.size())}};
  }

 private:
  std::vector<Photon> photons_;
  PhotonStats stats_;
};

void register_methods(PluginRegistrar& registrar) { registrar.add(plugin_method<FixedRadiusSplat>()); }

}  // namespace splat_example

CAUSTICBENCH_PLUGIN("fixed_radius_splat", "1.0", splat_example::register_methods)
