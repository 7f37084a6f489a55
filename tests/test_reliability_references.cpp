// The results store's guarantees about what it finds already stored (docs/results-format.md,
// "Guarantees"): damaged run records and references, a run measured against another copy of its
// reference, an asset edited in place, and references that do or do not depend on the machine's speed.
// The kills, full disks and concurrent processes: tests/test_reliability_store.cpp.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/files.h"
#include "core/parallel.h"
#include "tests/reliability/store_experiments.h"

using namespace causticbench;
using namespace causticbench::store_harness;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------
// Damaged records and references.

// Truncated, `{}` and wrong-checksum run records are not stored: the report shows them as failed (never
// ok), and the next run measures them again, naming each file and what was wrong.
TEST(Corruption, DamagedRunRecordsAreReportedAsFailedAndMeasuredAgain) {
  StoreFolder folder("damaged_runs", kFourRuns);
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  ResultPaths paths{folder.results};
  auto run_folder = [&](size_t index) { return fs::path(paths.run(experiment.name, experiment.runs[index].key)); };
  const std::string record = read_all(run_folder(0) / "record.json");
  std::ofstream(run_folder(0) / "record.json", std::ios::trunc) << record.substr(0, record.size() / 2);
  std::ofstream(run_folder(1) / "record.json", std::ios::trunc) << "{}";
  std::string image = read_all(run_folder(2) / "frame_0000.exr");
  image[image.size() / 2] ^= 0x5a;  // same size, other content
  std::ofstream(run_folder(2) / "frame_0000.exr", std::ios::binary | std::ios::trunc) << image;

  Finished report = run_process({"report", paths.experiment(experiment.name)}, folder.path("report.txt"));
  ASSERT_EQ(report.code, 0) << report.output;
  nlohmann::json results = nlohmann::json::parse(read_all(fs::path(paths.experiment(experiment.name)) / "results.json"));
  std::map<std::string, std::string> status;
  for (const nlohmann::json& run : results["runs"]) status[run.value("key", "")] = run.value("status", "");
  for (size_t index : {0, 1, 2}) EXPECT_EQ(status[experiment.runs[index].key], "failed") << index;
  EXPECT_EQ(status[experiment.runs[3].key], "ok");

  Finished rerun = folder.run();
  ASSERT_EQ(rerun.code, 0) << rerun.output;
  EXPECT_EQ(runs_now(rerun.output), 3) << rerun.output;
  for (const std::string& expected : std::vector<std::string>{
           (run_folder(0) / "record.json").string() + ": not valid JSON",
           (run_folder(1) / "record.json").string() + ": field 'key' is missing",
           "its image frame_0000.exr: its content does not match the checksum"})
    EXPECT_NE(rerun.output.find(expected), std::string::npos) << expected << " in:\n" << rerun.output;
  expect_complete(experiment, folder.results);
}

// A truncated reference EXR, a `{}` frame record and a truncated summary are found when the reference
// is next needed and computed again; the reference being deterministic, the new copy is the same bytes,
// so the runs measured against the old one stay stored.
TEST(Corruption, DamagedReferencesAreComputedAgain) {
  StoreFolder folder("damaged_reference");
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  const fs::path reference = ResultPaths{folder.results}.reference(experiment.variants[0].reference_key);
  const std::string image = read_all(reference / "frame_0000.exr");
  // A second experiment of the same reference has a run to do, so it needs the reference.
  const std::string second = folder.write("second.yaml", causticbench::testing::replace_once(
                                                             causticbench::testing::replace_once(kOneRun, "name: store", "name: second"),
                                                             "k: 10", "k: 11"));
  auto run_second = [&](const std::string& name) {
    return run_process({"run", second, "--results", folder.results, "--no-report"}, folder.path(name));
  };
  std::ofstream(reference / "frame_0000.exr", std::ios::trunc) << image.substr(0, image.size() / 2);
  Finished truncated = run_second("truncated.txt");
  ASSERT_EQ(truncated.code, 0) << truncated.output;
  EXPECT_NE(truncated.output.find("frame_0000.exr: " + std::to_string(image.size() / 2) + " bytes where its record says"),
            std::string::npos) << truncated.output;
  EXPECT_NE(truncated.output.find("computing"), std::string::npos) << truncated.output;
  EXPECT_EQ(read_all(reference / "frame_0000.exr"), image) << "same settings, same seed: the same bytes";

  std::ofstream(reference / "record_0000.json", std::ios::trunc) << "{}";
  std::ofstream(reference / "record.json", std::ios::trunc) << "{\"key\": ";
  Finished empty = run_process({"run", second, "--results", folder.results, "--no-report", "--force"}, folder.path("empty.txt"));
  ASSERT_EQ(empty.code, 0) << empty.output;
  EXPECT_NE(empty.output.find("record_0000.json: field 'frame' is missing; computing it again"), std::string::npos)
      << empty.output;
  Finished first = folder.run();
  EXPECT_NE(first.output.find("1 already stored, 0 run now"), std::string::npos) << first.output;
  expect_complete(experiment, folder.results);
}

// A stored run measured against another copy of its reference than the stored one (a time-capped
// reference computed again) is measured again, with a warning.
TEST(Corruption, ARunMeasuredAgainstAnotherCopyOfItsReferenceIsMeasuredAgain) {
  StoreFolder folder("other_copy");
  const Experiment experiment = folder.experiment();
  ASSERT_EQ(folder.run().code, 0);
  const fs::path record_path = fs::path(ResultPaths{folder.results}.run(experiment.name, experiment.runs[0].key)) / "record.json";
  nlohmann::json record = nlohmann::json::parse(read_all(record_path));
  record["reference_images"]["frame_0000.exr"]["xxhash"] = "0123456789abcdef";
  std::ofstream(record_path, std::ios::trunc) << record.dump(2);
  Finished rerun = folder.run();
  ASSERT_EQ(rerun.code, 0) << rerun.output;
  EXPECT_NE(rerun.output.find("was measured against another copy of reference"), std::string::npos) << rerun.output;
  EXPECT_EQ(runs_now(rerun.output), 1) << rerun.output;
  expect_complete(experiment, folder.results);
}

// A mesh the scene names, edited in place, leaves the scene file's text and so every key as they were:
// the reference stored with the old mesh is computed again (its record holds the scene's content hash),
// and the run measured against the old copy is measured again.
TEST(Corruption, AnEditedMeshComputesItsReferenceAndRunsAgain) {
  // A glass octahedron of half-diagonal `size` at the sphere's place.
  auto octahedron = [](double size) {
    std::string text;
    for (const char* corner : {"1 0 0", "-1 0 0", "0 1 0", "0 -1 0", "0 0 1", "0 0 -1"}) {
      std::istringstream in(corner);
      double x, y, z;
      in >> x >> y >> z;
      text += fmt::format("v {} {} {}\n", x * size, y * size + 0.6, z * size);
    }
    return text + "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
  };
  StoreFolder folder("edited_mesh");
  folder.write("gem.obj", octahedron(0.4));
  folder.write("scene.yaml", causticbench::testing::replace_once(
                                 causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                     "resolution: [40, 40]", "resolution: [16, 16]"),
                                 "shape: {type: sphere, radius: 0.4}", "shape: {type: mesh, asset: gem.obj, smooth_normals: false}"));
  const Experiment before = folder.experiment();
  Finished first = folder.run();
  ASSERT_EQ(first.code, 0) << first.output;
  EXPECT_EQ(runs_now(first.output), 1) << first.output;
  const fs::path reference = ResultPaths{folder.results}.reference(before.variants[0].reference_key);
  EXPECT_EQ(nlohmann::json::parse(read_all(reference / "record_0000.json"))["scene_content"], before.variants[0].content_hash);
  Finished unchanged = folder.run();
  EXPECT_EQ(runs_now(unchanged.output), 0) << unchanged.output;

  folder.write("gem.obj", octahedron(0.3));
  const Experiment after = folder.experiment();
  ASSERT_EQ(after.variants[0].reference_key, before.variants[0].reference_key) << "the keys hash the scene file's text";
  ASSERT_EQ(after.runs[0].key, before.runs[0].key);
  ASSERT_NE(after.variants[0].content_hash, before.variants[0].content_hash);
  Finished edited = folder.run();
  ASSERT_EQ(edited.code, 0) << edited.output;
  EXPECT_NE(edited.output.find("computed for other scene content"), std::string::npos) << edited.output;
  EXPECT_EQ(runs_now(edited.output), 1) << edited.output;
  EXPECT_EQ(nlohmann::json::parse(read_all(reference / "record_0000.json"))["scene_content"], after.variants[0].content_hash);
  expect_complete(after, folder.results);
}

// ---------------------------------------------------------------------------------------------------
// References that do and do not depend on the machine.

// Stopped on its pass count or its reference error, the reference is the same image on 1 and 2 threads.
TEST(Reference, SameSeedGivesTheSameImageOnAnyThreadCount) {
  Scene scene = causticbench::testing::scene_from_yaml(causticbench::testing::replace_once(
      causticbench::testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
  const std::vector<std::vector<std::string>> stops = {
      {"photons_per_pass=20000", "max_passes=3", "target_error=0", "max_seconds=0"},
      {"photons_per_pass=20000", "max_passes=1000", "target_error=0.015", "min_passes=2", "max_seconds=0"}};
  for (const std::vector<std::string>& knobs : stops) {
    auto render_on = [&](int threads) {
      ThreadLimit limit(threads);
      return causticbench::testing::render(scene, "reference", knobs);
    };
    FrameResult one = render_on(1), two = render_on(2);
    EXPECT_EQ(one.method_record["passes"], two.method_record["passes"]);
    EXPECT_EQ(one.method_record["stop_reason"], knobs[2] == "target_error=0" ? "max_passes" : "target_error");
    EXPECT_TRUE(one.caustic.values() == two.caustic.values()) << knobs[2];
    EXPECT_EQ(encode_exr(one.caustic), encode_exr(two.caustic)) << "the stored bytes too";
  }
}

// Stopped on its time cap, the reference is stored as not converged with the reason; the runs measured
// against it and the report say so.
TEST(Reference, ATimeCappedReferenceIsMarkedAndItsRunsSaySo) {
  StoreFolder folder("time_cap", causticbench::testing::replace_once(
                                     kOneRun, "reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0, max_seconds: 0}",
                                     kTimeCapped));
  const Experiment experiment = folder.experiment();
  Finished run = run_process({"run", folder.experiment_file, "--results", folder.results}, folder.path("out.txt"));
  ASSERT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("is not converged"), std::string::npos) << run.output;
  const fs::path reference = ResultPaths{folder.results}.reference(experiment.variants[0].reference_key);
  nlohmann::json frame = nlohmann::json::parse(read_all(reference / "record_0000.json"));
  EXPECT_EQ(frame["stop_reason"], "max_seconds");
  EXPECT_EQ(frame["converged"], false);
  EXPECT_NE(frame.value("unconverged_reason", std::string()).find("time cap (max_seconds"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(read_all(reference / "record.json"))["converged"], false);
  StoredRun stored = inspect_stored_run(ResultPaths{folder.results}.run(experiment.name, experiment.runs[0].key));
  EXPECT_EQ(stored.record["reference_converged"], false);
  EXPECT_EQ(stored.record["reference_unconverged"], frame["unconverged_reason"]);
  const std::string markdown = read_all(fs::path(folder.results) / experiment.name / "report.md");
  EXPECT_NE(markdown.find("NOT converged"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("1 run(s) were measured against a reference that stopped on its time cap"), std::string::npos)
      << markdown;
}

// The reference's G-buffer names its channels (GBuffer::channel_names), so that tev or `oiiotool --info`
// say which is which; GBuffer::read_image puts a stored file's channels back in to_image()'s order by
// name, for these files and for those written before, whose unnamed channels (R, G, B, A, channel4 ...)
// OpenImageIO reads in another order: read by index, channel 10 of an old file was albedo.B, so a
// receiver darker than albedo 0.5 fell out of the receiver mask.
TEST(Reference, ItsGBufferNamesItsChannelsAndOldFilesReadTheSame) {
  StoreFolder folder("gbuffer_names", kOneRun);
  const Experiment experiment = folder.experiment();
  Finished run = run_process({"run", folder.experiment_file, "--results", folder.results, "--no-report"}, folder.path("out.txt"));
  ASSERT_EQ(run.code, 0) << run.output;
  const fs::path stored = fs::path(ResultPaths{folder.results}.reference(experiment.variants[0].reference_key)) / "gbuffer_0000.exr";
  std::vector<std::string> names;
  const Image raw = read_exr(stored.string(), &names);
  std::vector<std::string> sorted_names = names, expected = GBuffer::channel_names();
  std::sort(sorted_names.begin(), sorted_names.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(sorted_names, expected);

  // A G-buffer with a dark receiver (albedo 0.3), written with names and in the old unnamed way.
  GBuffer gbuffer;
  gbuffer.width = 4, gbuffer.height = 2;
  for (size_t i = 0; i < gbuffer.pixel_count(); ++i) {
    gbuffer.position.push_back(Vec3(float(i), 2.0f * i, 3.0f * i));
    gbuffer.normal.push_back(Vec3(0.0f, 1.0f, 0.0f));
    gbuffer.albedo.push_back(Color(i < 4 ? 0.3f : 0.0f));
    gbuffer.object.push_back(i < 4 ? 0 : 1);
    gbuffer.receiver.push_back(i < 4 ? 1 : 0);
    gbuffer.footprint.push_back(0.01f * (i + 1));
  }
  const Image written = gbuffer.to_image();
  write_exr(written, folder.path("named.exr"), GBuffer::channel_names());
  write_exr(written, folder.path("unnamed.exr"));
  for (const char* file : {"named.exr", "unnamed.exr"}) {
    const Image read = GBuffer::read_image(folder.path(file));
    EXPECT_TRUE(read.values() == written.values()) << file;
    for (size_t i = 0; i < gbuffer.pixel_count(); ++i)
      EXPECT_EQ(read.at(i, GBuffer::kReceiverChannel) > 0.5f, gbuffer.receiver[i] == 1) << file << " pixel " << i;
  }
  // Read by index, the old file's channel 10 is not the receiver mask.
  const Image by_index = read_exr(folder.path("unnamed.exr"));
  EXPECT_NE(by_index.at(0, GBuffer::kReceiverChannel) > 0.5f, true);
}
