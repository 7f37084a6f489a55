// Bad input gets a clear error naming file, line, column, key and what was expected, and exit code 2.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/scene.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::run_command;
using causticbench::testing::scene_from_yaml;

namespace {

const char* kValidScene = R"(camera: {position: [0, 2, 3], look_at: [0, 0, 0], resolution: [16, 16]}
lights:
  - {type: directional, direction: [0, -1, 0], irradiance: 1}
objects:
  - shape: {type: quad, size: [4, 4]}
    material: {type: diffuse, albedo: 0.5}
  - shape: {type: sphere, radius: 0.5}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.5, 0]}
)";

std::string error_of(const std::string& yaml) {
  return causticbench::testing::input_error_message([&] { scene_from_yaml(yaml, "bad.yaml"); });
}

const auto replace = causticbench::testing::replace_once;

}  // namespace

TEST(Validation, ValidSceneLoads) {
  Scene scene = scene_from_yaml(kValidScene);
  EXPECT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.camera.width, 16);
  EXPECT_TRUE(scene.has_specular_object());
}

TEST(Validation, UnknownKeySuggestsTheClosest) {
  std::string message = error_of(replace(kValidScene, "material: {type: glass, ior: 1.5}", "material: {type: glass, iro: 1.5}"));
  EXPECT_NE(message.find("bad.yaml:8:"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown key 'iro'"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'ior'"), std::string::npos) << message;
}

TEST(Validation, UnknownTopLevelKey) {
  std::string message = error_of(std::string(kValidScene) + "lihgts: []\n");
  EXPECT_NE(message.find("bad.yaml:10:1"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'lights'"), std::string::npos) << message;
}

TEST(Validation, WrongTypeNamesExpectedAndFound) {
  std::string message = error_of(replace(kValidScene, "radius: 0.5", "radius: large"));
  EXPECT_NE(message.find("bad.yaml:7:"), std::string::npos) << message;
  EXPECT_NE(message.find("shape.radius"), std::string::npos) << message;
  EXPECT_NE(message.find("expected a number"), std::string::npos) << message;
  EXPECT_NE(message.find("found 'large'"), std::string::npos) << message;
}

TEST(Validation, OutOfRange) {
  std::string message = error_of(replace(kValidScene, "ior: 1.5", "ior: 0.5"));
  EXPECT_NE(message.find("bad.yaml:8:"), std::string::npos) << message;
  EXPECT_NE(message.find("[1, 4]"), std::string::npos) << message;
  EXPECT_NE(message.find("found '0.5'"), std::string::npos) << message;
}

TEST(Validation, NaNIsRejected) {
  std::string message = error_of(replace(kValidScene, "irradiance: 1", "irradiance: .nan"));
  EXPECT_NE(message.find("bad.yaml:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("finite"), std::string::npos) << message;
}

TEST(Validation, UnknownChoiceSuggests) {
  std::string message = error_of(replace(kValidScene, "type: sphere", "type: spehre"));
  EXPECT_NE(message.find("did you mean 'sphere'"), std::string::npos) << message;
}

TEST(Validation, MissingAssetNamesWhereToGetIt) {
  std::string message = error_of(replace(kValidScene, "{type: sphere, radius: 0.5}", "{type: mesh, asset: no_such_mesh_anywhere}"));
  EXPECT_NE(message.find("bad.yaml:7:"), std::string::npos) << message;
  EXPECT_NE(message.find("mesh asset 'no_such_mesh_anywhere' not found"), std::string::npos) << message;
  EXPECT_NE(message.find("CAUSTICBENCH_ASSET_PATH"), std::string::npos) << message;
}

TEST(Validation, MissingRequiredKey) {
  std::string message = error_of(replace(kValidScene, ", radius: 0.5", ""));
  EXPECT_NE(message.find("required key 'radius'"), std::string::npos) << message;
}

TEST(Validation, YamlSyntaxErrorHasPosition) {
  std::string message = error_of("camera: {position: [0, 2, 3\nlights: []\n");
  EXPECT_NE(message.find("bad.yaml:"), std::string::npos) << message;
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;
}

TEST(Validation, GlassOnOpenShapeIsRejected) {
  std::string message = error_of(replace(kValidScene, "{type: sphere, radius: 0.5}", "{type: disk, radius: 0.5}"));
  EXPECT_NE(message.find("glass only on closed shapes"), std::string::npos) << message;
}

TEST(Validation, UnknownMethodParameterSuggests) {
  ParamDict params;
  params.set_assignment("photon=1000", "--set");
  try {
    params.resolve(find_method("photon_map").info().params, "photon_map");
    FAIL() << "no error";
  } catch (const InputError& error) {
    std::string message = error.what();
    EXPECT_NE(message.find("unknown parameter 'photon'"), std::string::npos) << message;
    EXPECT_NE(message.find("did you mean 'photons'"), std::string::npos) << message;
  }
}

TEST(Validation, MethodParameterRangeAndType) {
  ParamDict params;
  params.set_assignment("k=0", "--set");
  EXPECT_THROW(params.resolve(find_method("photon_map").info().params, "photon_map"), InputError);
  ParamDict fractional;
  fractional.set_assignment("k=2.5", "--set");
  EXPECT_THROW(fractional.resolve(find_method("photon_map").info().params, "photon_map"), InputError);
  ParamDict not_a_number;
  not_a_number.set_assignment("max_radius=nan", "--set");
  EXPECT_THROW(not_a_number.resolve(find_method("photon_map").info().params, "photon_map"), InputError);
}

TEST(Validation, UnknownMethodSuggests) {
  try {
    find_method("photonmap");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("did you mean 'photon_map'"), std::string::npos) << error.what();
  }
}

// The command line turns input errors into exit code 2 and writes nothing.
TEST(Validation, CommandLineExitsWithTwoAndWritesNothing) {
  namespace fs = std::filesystem;
  fs::path folder = fs::temp_directory_path() / "causticbench_validation_test";
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::string bad = (folder / "bad.yaml").string();
  std::ofstream(bad) << replace(kValidScene, "ior: 1.5", "ior: 9");
  std::string output;
  fs::path out = folder / "out";
  int code = run_command(std::string(CAUSTICBENCH_BINARY) + " render " + bad + " --out " + out.string(), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("bad.yaml:8:"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out)) << "output folder created despite the error";

  std::string good = (folder / "good.yaml").string();
  std::ofstream(good) << kValidScene;
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " render " + good + " --set k=3 --out " + out.string(), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("unknown parameter 'k' for method 'reference'"), std::string::npos) << output;
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " validate " + good, output);
  EXPECT_EQ(code, 0) << output;
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " render " + good + " --resolution 12by3 --out " + out.string(), output);
  EXPECT_EQ(code, 2) << output;
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " render " + good + " --bogus-flag --out " + out.string(), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(folder);
}

// Every shipped scene file validates.
TEST(Validation, ShippedScenesValidate) {
  namespace fs = std::filesystem;
  int count = 0;
  for (const auto& entry : fs::directory_iterator(CAUSTICBENCH_SCENES)) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(load_scene(entry.path().string())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 8);
}

TEST(Validation, ObjectKeyframesNeedDistinctFrames) {
  std::string message = error_of(replace(kValidScene, "    transform: {translate: [0, 0.5, 0]}",
                                         "    animation: {keyframes: [{frame: 0, translate: [0, 0.5, 0]}, "
                                         "{frame: 0, translate: [1, 0.5, 0]}]}"));
  EXPECT_NE(message.find("distinct frame numbers for 'translate'"), std::string::npos) << message;
}

TEST(Validation, KeyframeWithNothingTheOwnerCanAnimate) {
  // An environment image cannot be animated: the value is named, with what the keyframe may hold.
  std::string scene = replace(kValidScene, "{type: directional, direction: [0, -1, 0], irradiance: 1}",
                              "{type: environment, image: forest, animation: {keyframes: [{frame: 0, "
                              "rotation_degrees: 0}, {frame: 9, rotation_degrees: 90}]}}");
  std::string message = error_of(scene);
  EXPECT_NE(message.find("unknown key 'rotation_degrees'"), std::string::npos) << message;
  EXPECT_NE(message.find("known keys: frame"), std::string::npos) << message;
  message = error_of(replace(kValidScene, "    transform: {translate: [0, 0.5, 0]}",
                             "    animation: {keyframes: [{frame: 0}, {frame: 5}]}"));
  EXPECT_NE(message.find("a frame and at least one animated value"), std::string::npos) << message;
}

TEST(Validation, AnimatedObjectInterpolatesItsKeyframes) {
  Scene scene = scene_from_yaml(replace(kValidScene, "    transform: {translate: [0, 0.5, 0]}",
                                        "    transform: {rotate: [0, 30, 0]}\n"
                                        "    animation: {keyframes: [{frame: 0, translate: [0, 0.5, 0]}, "
                                        "{frame: 10, translate: [2, 0.5, 0]}]}"));
  const AnimatedTransform& transform = scene.objects[1].transform;
  EXPECT_DOUBLE_EQ(transform.translate.at(5).x, 1.0);
  EXPECT_DOUBLE_EQ(transform.translate.at(20).x, 2.0);
  EXPECT_DOUBLE_EQ(transform.rotate.at(5).y, 30.0);  // the still part of the transform stays
}

TEST(Validation, AnimatedLightKeepsAndChecksItsStillValue) {
  std::string animated = "{type: directional, direction: [0, -1, 0], irradiance: 1, animation: {keyframes: "
                         "[{frame: 0, direction: [0, -1, 0]}, {frame: 4, direction: [1, -1, 0]}]}}";
  Scene scene = scene_from_yaml(replace(kValidScene, "{type: directional, direction: [0, -1, 0], irradiance: 1}", animated));
  EXPECT_DOUBLE_EQ(scene.lights[0].direction.at(2).x, 0.5);
  std::string message = error_of(replace(kValidScene, "{type: directional, direction: [0, -1, 0], irradiance: 1}",
                                         replace(animated, "direction: [0, -1, 0], irradiance", "direction: [0, -1], irradiance")));
  EXPECT_NE(message.find("a list of 3 numbers"), std::string::npos) << message;
}
