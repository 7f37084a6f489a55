// The posed-frame scene export (core/scene_export.h) that external hands its program: every shipped scene,
// posed at a frame in the middle of its animation, written and read back as a scene of one frame, is the
// same frame bit for bit (object transforms, posed lights, world triangles and their normals, bounding
// spheres, the G-buffer through the camera) and photon_map renders the same E_c from it; world.json's
// matrices, light directions and triangle files are the frame's.
#include <cstring>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/files.h"
#include "core/mesh_file.h"
#include "core/scene_export.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool same_bits(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() && same_bits(a.values(), b.values());
}

// The triangles of `mesh` as corner positions and normals, in triangle order: what the tracer sees, whatever
// the numbering of the vertices.
std::vector<Vec3> corners(const TriangleMesh& mesh, bool normals) {
  std::vector<Vec3> result;
  for (const glm::uvec3& triangle : mesh.triangles)
    for (int k = 0; k < 3; ++k) result.push_back(normals ? mesh.normals[triangle[k]] : mesh.positions[triangle[k]]);
  return result;
}

// The frame of `scene` a test poses: the middle of an animation, so that every track is evaluated
// between keyframes, or 0.
int posed_frame(const Scene& scene) { return scene.frames / 2; }

void expect_same_frame(const SceneFrame& original, const SceneFrame& exported, const std::string& where) {
  ASSERT_EQ(original.transforms.size(), exported.transforms.size()) << where;
  for (size_t i = 0; i < original.transforms.size(); ++i) {
    const std::string object = where + " object " + std::to_string(i);
    EXPECT_TRUE(std::memcmp(&original.transforms[i].matrix, &exported.transforms[i].matrix, sizeof(glm::dmat4)) == 0) << object;
    EXPECT_TRUE(same_bits(corners(original.world_meshes[i], false), corners(exported.world_meshes[i], false))) << object;
    EXPECT_TRUE(same_bits(corners(original.world_meshes[i], true), corners(exported.world_meshes[i], true))) << object;
    EXPECT_EQ(original.world_meshes[i].smooth, exported.world_meshes[i].smooth) << object;
    EXPECT_EQ(original.bounds[i].center, exported.bounds[i].center) << object;
    EXPECT_EQ(original.bounds[i].radius, exported.bounds[i].radius) << object;
  }
  ASSERT_EQ(original.lights.size(), exported.lights.size()) << where;
  for (size_t i = 0; i < original.lights.size(); ++i) {
    const LightFrame &a = original.lights[i], &b = exported.lights[i];
    EXPECT_EQ(a.direction_to_light, b.direction_to_light) << where << " light " << i;
    EXPECT_EQ(a.position, b.position) << where << " light " << i;
    EXPECT_EQ(a.cos_cone, b.cos_cone) << where << " light " << i;
    EXPECT_EQ(a.spot_sigma, b.spot_sigma) << where << " light " << i;
    EXPECT_EQ(a.light->irradiance, b.light->irradiance) << where << " light " << i;
    EXPECT_EQ(a.light->intensity, b.light->intensity) << where << " light " << i;
    if (a.light->environment) {
      ASSERT_TRUE(b.light->environment) << where << " light " << i;
      EXPECT_TRUE(same_bits(a.light->environment->pixels(), b.light->environment->pixels())) << where << " light " << i;
    }
  }
}

void expect_same_gbuffer(const GBuffer& a, const GBuffer& b, const std::string& where) {
  EXPECT_TRUE(same_bits(a.position, b.position)) << where;
  EXPECT_TRUE(same_bits(a.normal, b.normal)) << where;
  EXPECT_TRUE(same_bits(a.albedo, b.albedo)) << where;
  EXPECT_TRUE(same_bits(a.object, b.object)) << where;
  EXPECT_TRUE(same_bits(a.receiver, b.receiver)) << where;
  EXPECT_TRUE(same_bits(a.footprint, b.footprint)) << where;
}

TEST(SceneExport, EveryShippedSceneReadsBackAsTheSameFrame) {
  size_t scenes = 0;
  for (const auto& entry : fs::directory_iterator(testing::shipped_scenes())) {
    if (entry.path().extension() != ".yaml") continue;
    Scene scene = load_scene(entry.path().string());
    set_resolution(scene, 24, 18);
    const int frame = posed_frame(scene);
    const std::string where = fmt::format("{} at frame {}", entry.path().filename().string(), frame);
    testing::TemporaryFolder folder("scene_export_" + entry.path().stem().string());
    SceneExporter exporter(folder.path());
    const PosedFrame original(scene, frame);
    const Scene exported = load_scene(exporter.write(original.frame));
    EXPECT_EQ(exported.frames, 1) << where;
    const PosedFrame read_back(exported, 0);
    expect_same_frame(original.frame, read_back.frame, where);
    expect_same_gbuffer(original.gbuffer, read_back.gbuffer, where);
    if (scene.has_specular_object()) {
      const FrameResult a = testing::render(scene, "photon_map", {"photons=4000"}, frame);
      const FrameResult b = testing::render(exported, "photon_map", {"photons=4000"}, 0);
      EXPECT_TRUE(same_bits(a.caustic, b.caustic)) << where << ": photon_map's E_c";
    }
    ++scenes;
  }
  EXPECT_GE(scenes, 10u);
}

// world.json: each object's matrix is its transform's, each triangle shape's file holds its world-space
// triangles, each distant light's direction is the posed one; files that did not change are not written
// again, and a moved object's triangles are.
TEST(SceneExport, WorldFileHoldsTheFrameInWorldSpace) {
  Scene scene = load_scene(testing::shipped_scenes() + "/water_pool.yaml");
  set_resolution(scene, 16, 16);
  testing::TemporaryFolder folder("scene_export_world");
  SceneExporter exporter(folder.path());
  for (int frame : {3, 4}) {
    const SceneFrame posed(scene, frame);
    exporter.write(posed);
    const nlohmann::json world = nlohmann::json::parse(read_text(exporter.world_path()));
    EXPECT_EQ(world["frame"], frame);
    size_t meshes = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
      const nlohmann::json& object = world["objects"][i];
      for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 4; ++column)
          EXPECT_EQ(object["object_to_world"][row][column].get<double>(), posed.transforms[i].matrix[column][row]);
      EXPECT_EQ(object["makes_caustics"].get<bool>(), scene.objects[i].material.is_specular());
      if (!object.contains("triangles")) {
        EXPECT_TRUE(scene.objects[i].shape.is_analytic());
        continue;
      }
      ++meshes;
      const std::shared_ptr<const TriangleMesh> triangles =
          load_mesh(folder.path(object["triangles"].get<std::string>()), true, 0.0, SourceLocation{"test"});
      EXPECT_TRUE(same_bits(corners(*triangles, false), corners(posed.world_meshes[i], false))) << "frame " << frame << " object " << i;
      EXPECT_TRUE(same_bits(corners(*triangles, true), corners(posed.world_meshes[i], true))) << "frame " << frame << " object " << i;
    }
    EXPECT_GT(meshes, 0u);
    for (size_t i = 0; i < posed.lights.size(); ++i) {
      const LightKind kind = posed.lights[i].light->kind;
      EXPECT_EQ(world["lights"][i]["type"], kind == LightKind::directional ? "directional" : kind == LightKind::point ? "point"
                                           : kind == LightKind::gaussian_spot ? "gaussian_spot" : "environment_image");
      if (kind != LightKind::directional && kind != LightKind::gaussian_spot) continue;
      const nlohmann::json& direction = world["lights"][i]["direction_to_light"];
      EXPECT_EQ(Vec3(direction[0].get<float>(), direction[1].get<float>(), direction[2].get<float>()), posed.lights[i].direction_to_light);
    }
  }
}

// `causticbench export`: the files of one frame as external hands them over, with the G-buffer of that
// frame; a frame outside the animation is refused with exit 2 before anything is written.
TEST(SceneExport, TheExportCommandWritesOneFramesFiles) {
  testing::TemporaryFolder folder("scene_export_command");
  const std::string scene = testing::shipped_scenes() + "/water_pool.yaml";
  std::string output;
  ASSERT_EQ(testing::run_command(std::string(CAUSTICBENCH_BINARY) + " export " + scene + " --frame 7 --resolution 32x24 --out " +
                                     folder.path("frame"),
                                 output),
            0)
      << output;
  EXPECT_NE(output.find("gbuffer.exr, scene.json, world.json"), std::string::npos) << output;
  Scene original = load_scene(scene);
  set_resolution(original, 32, 24);
  const PosedFrame posed(original, 7);
  const Scene exported = load_scene(folder.path("frame/scene.json"));
  expect_same_gbuffer(posed.gbuffer, PosedFrame(exported, 0).gbuffer, "export --frame 7");
  EXPECT_TRUE(same_bits(GBuffer::read_image(folder.path("frame/gbuffer.exr")), posed.gbuffer.to_image()));
  EXPECT_EQ(nlohmann::json::parse(read_text(folder.path("frame/world.json")))["frame"], 7);

  EXPECT_EQ(testing::run_command(std::string(CAUSTICBENCH_BINARY) + " export " + scene + " --frame 30 --out " + folder.path("late"), output),
            2);
  EXPECT_NE(output.find("--frame: expected 0 to 29"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(folder.path("late")));
}

}  // namespace
}  // namespace causticbench
