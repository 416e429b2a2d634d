// photoscene batch's library: manifests (both forms, and the errors of a bad one), records,
// the exit status rule, summary.csv / index.html, and the Slurm array script.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/pipeline/batch.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;
using batch::Status;

fs::path writeFile(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p;
}

// The InputError message of reading `manifest`, or "" when it reads.
std::string manifestError(const fs::path& manifest) {
  try {
    batch::readManifest(manifest);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Batch_Manifest, text_lines_resolve_against_the_manifest_and_name_by_folder) {
  io::TempDir dir;
  const fs::path m =
      writeFile(dir / "sets/rooms.txt",
                "# a comment line\n\n  ../data/kitchen/scene.json  # trailing comment\n"
                "/abs/bath/scene.json\n");
  const auto s = batch::readManifest(m);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].scene, (dir / "data/kitchen/scene.json").lexically_normal());
  EXPECT_EQ(s[0].name, "kitchen");
  EXPECT_EQ(s[0].where, "line 3");
  EXPECT_EQ(s[1].scene, fs::path("/abs/bath/scene.json"));
  EXPECT_EQ(s[1].name, "bath");
  EXPECT_FALSE(s[0].options.preset.has_value());
}

TEST(Batch_Manifest, json_entries_carry_names_and_options) {
  io::TempDir dir;
  const fs::path m = writeFile(dir / "m.json", R"({"version": 1, "scenes": [
      {"scene": "a/scene.json"},
      {"scene": "a/scene.json", "name": "a-fast", "options": {"preset": "fast", "texture_size": 64}}]})");
  const auto s = batch::readManifest(m);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].name, "a");
  EXPECT_EQ(s[1].name, "a-fast");
  EXPECT_EQ(s[1].options.preset.value_or(""), "fast");
  EXPECT_EQ(s[1].options.textureSize.value_or(0), 64);
  EXPECT_EQ(s[1].scene, dir / "a/scene.json");
}

TEST(Batch_Manifest, bad_manifests_name_the_file_the_line_or_key_and_what_was_expected) {
  io::TempDir dir;
  struct Case {
    std::string file, text, expect1, expect2;
  };
  const std::vector<Case> cases = {
      {"dup.txt", "a/scene.json\n# c\nother/a/scene.json\n", "line 3",
       "already the name of line 1"},
      {"empty.txt", "# nothing\n\n", "empty.txt", "at least one scene"},
      {"dot.txt", "x/.hidden/scene.json\n", "line 1", "expected a scene name"},
      {"version.json", R"({"version": 2, "scenes": [{"scene": "a/scene.json"}]})", "version",
       "expected 1"},
      {"noscenes.json", R"({"version": 1, "scenes": []})", "scenes", "non-empty array"},
      {"preset.json",
       R"({"version": 1, "scenes": [{"scene": "a/scene.json"}, {"scene": "b/scene.json", "options": {"preset": "quick"}}]})",
       "scenes[1].options.preset", "\"fast\", \"balanced\" or \"paper\""},
      {"size.json",
       R"({"version": 1, "scenes": [{"scene": "a/scene.json", "options": {"texture_size": 2}}]})",
       "scenes[0].options.texture_size", "4 to 16384"},
      {"key.json", R"({"version": 1, "scenes": [{"scene": "a/scene.json", "nmae": "x"}]})",
       "scenes[0].nmae", "unknown key"},
      {"name.json", R"({"version": 1, "scenes": [{"scene": "a/scene.json", "name": "../up"}]})",
       "scenes[0].name", "expected a scene name"},
      {"dupname.json",
       R"({"version": 1, "scenes": [{"scene": "a/scene.json", "name": "x"}, {"scene": "b/scene.json", "name": "x"}]})",
       "scenes[1].name", "unique"},
      {"missing.json", R"({"version": 1, "scenes": [{"name": "x"}]})", "scenes[0].scene",
       "missing"},
      {"syntax.json", "{\"version\": 1,\n \"scenes\": [}\n", "syntax.json", "line 2"},
  };
  for (const Case& c : cases) {
    const std::string msg = manifestError(writeFile(dir / c.file, c.text));
    EXPECT_NE(msg.find(c.file), std::string::npos) << c.file << ": " << msg;
    EXPECT_NE(msg.find(c.expect1), std::string::npos) << c.file << ": " << msg;
    EXPECT_NE(msg.find(c.expect2), std::string::npos) << c.file << ": " << msg;
  }
  EXPECT_NE(manifestError(dir / "absent.txt").find("absent.txt"), std::string::npos);
}

TEST(Batch_Records, round_trip_and_the_exit_status_rule) {
  io::TempDir dir;
  batch::SceneRecord r;
  r.name = "kitchen";
  r.status = Status::BadInput;
  r.exitCode = 2;
  r.error = "scene.json: geometry: expected a path";
  r.attempts = 3;
  batch::writeRecord(dir.path(), r);
  const batch::SceneRecord back = batch::readRecord(dir.path(), "kitchen");
  EXPECT_EQ(back.status, Status::BadInput);
  EXPECT_EQ(back.exitCode.value_or(-1), 2);
  EXPECT_EQ(back.error, r.error);
  EXPECT_EQ(back.attempts, 3);
  EXPECT_EQ(batch::readRecord(dir.path(), "absent").status, Status::Pending);

  // a `running` record whose process is gone on this host reads as pending
  batch::SceneRecord running;
  running.name = "gone";
  running.status = Status::Running;
  char host[256] = {0};
  gethostname(host, sizeof(host) - 1);
  running.host = host;
  running.pid = 999999999;  // above pid_max: no such process
  batch::writeRecord(dir.path(), running);
  const batch::SceneRecord stale = batch::readRecord(dir.path(), "gone");
  EXPECT_EQ(stale.status, Status::Pending);
  EXPECT_NE(stale.error.find("ended without recording"), std::string::npos) << stale.error;

  auto rec = [](Status s) {
    batch::SceneRecord x;
    x.status = s;
    return x;
  };
  EXPECT_EQ(batch::exitStatus({rec(Status::Done), rec(Status::Done)}), 0);
  EXPECT_EQ(batch::exitStatus({rec(Status::Done), rec(Status::BadInput)}), 2);
  EXPECT_EQ(batch::exitStatus({rec(Status::BadInput), rec(Status::Failed)}), 1);
  EXPECT_EQ(batch::exitStatus({rec(Status::Done), rec(Status::Pending)}), 1);
  EXPECT_EQ(batch::exitStatus({rec(Status::Running), rec(Status::BadInput)}), 1);
}

batch::Batch twoSceneBatch(const fs::path& root) {
  batch::Batch b;
  b.root = root;
  b.manifest = root / "m.txt";
  b.scenes.resize(2);
  b.scenes[0].scene = "/data/a/scene.json";
  b.scenes[0].name = "a";
  b.scenes[1].scene = "/data/b b/scene.json";
  b.scenes[1].name = "b";
  b.scenes[1].options.preset = "paper";
  b.options.preset = "fast";
  b.options.textureSize = 16;
  return b;
}

TEST(Batch_Summary, one_row_per_scene_with_stage_seconds_and_ground_truth_metrics) {
  io::TempDir dir;
  const batch::Batch b = twoSceneBatch(dir.path());
  batch::writeBatchFile(b);
  const batch::Batch back = batch::readBatchFile(dir.path());
  ASSERT_EQ(back.scenes.size(), 2u);
  EXPECT_EQ(back.scenes[1].options.preset.value_or(""), "paper");
  EXPECT_EQ(back.options.textureSize.value_or(0), 16);

  // scene a done, with stage times and view / novel scores; b failed
  fs::create_directories(dir / "a");
  io::writeJsonFile(dir / "a/metrics.json",
                    {{"preset", "fast"},
                     {"stages", {{"fit", 2.5}, {"geometry", 0.25}, {"zzz_new_stage", 1.0}}},
                     {"views",
                      {{{"srgb255", {{"rmse", 10.0}, {"psnr", 20.0}, {"ssim", 0.5}}}},
                       {{"srgb255", {{"rmse", 20.0}, {"psnr", 30.0}, {"ssim", 0.7}}}}}},
                     {"novel", {{{"name", "n0"}, {"srgb255", {{"rmse", 7.0}, {"ssim", 0.9}}}}}},
                     {"relit", nlohmann::json::array()}});
  std::ofstream(dir / "a/report.html") << "<html></html>";
  std::vector<batch::SceneRecord> records(2);
  records[0].name = "a";
  records[0].status = Status::Done;
  records[0].exitCode = 0;
  records[0].seconds = 4.0;
  records[1].name = "b";
  records[1].status = Status::Failed;
  records[1].exitCode = 1;
  records[1].error = "stage fit: out of memory, \"badly\"";
  batch::writeSummary(b, records);

  std::ifstream csv(dir / "summary.csv");
  std::string header, rowA, rowB, extra;
  std::getline(csv, header);
  std::getline(csv, rowA);
  std::getline(csv, rowB);
  EXPECT_FALSE(std::getline(csv, extra));
  // stages in pipeline order, unknown ones after
  EXPECT_EQ(header,
            "name,status,exit_code,seconds,preset,seconds_geometry,seconds_fit,seconds_zzz_new_"
            "stage,view_rmse,"
            "view_psnr,view_ssim,novel_rmse,novel_ssim,relit_rmse,relit_ssim,error");
  EXPECT_EQ(rowA, "a,done,0,4,fast,0.25,2.5,1,15,25,0.6,7,0.9,,,");
  EXPECT_EQ(rowB, "b,failed,1,,paper,,,,,,,,,,,\"stage fit: out of memory, \"\"badly\"\"\"");
  const std::string index = io::readTextFile(dir / "index.html");
  EXPECT_NE(index.find("href=\"a/report.html\""), std::string::npos);
  EXPECT_EQ(index.find("href=\"b/report.html\""), std::string::npos);  // b has no report
  EXPECT_NE(index.find("1 done, 1 failed"), std::string::npos);
  EXPECT_NE(index.find("&quot;badly&quot;"), std::string::npos);  // escaped

  // summary.csv keeps the contract's four words: a running scene is pending there (index.html
  // says running)
  records[1].status = Status::Running;
  records[1].exitCode.reset();
  records[1].error.clear();
  batch::writeSummary(b, records);
  std::ifstream again(dir / "summary.csv");
  std::getline(again, header);
  std::getline(again, rowA);
  std::getline(again, rowB);
  EXPECT_EQ(rowB.substr(0, 12), "b,pending,,,");
  EXPECT_NE(io::readTextFile(dir / "index.html").find("<td>running</td>"), std::string::npos);
}

TEST(Batch_Slurm, array_script_sizes_tasks_by_preset_and_runs_the_task_entry_point) {
  io::TempDir dir;
  const batch::Batch b = twoSceneBatch(dir.path());
  EXPECT_EQ(batch::arrayRanges({0, 1, 2, 5, 7, 8}), "0-2,5,7-8");
  EXPECT_EQ(batch::arrayRanges({3}), "3");
  batch::SlurmOptions o;
  o.maxParallel = 4;
  o.partition = "gpu";
  const std::string s = batch::slurmScript(b, {0, 1}, o, "/opt/bin/photoscene");
  EXPECT_NE(s.find("#SBATCH --array=0-1%4\n"), std::string::npos) << s;
  EXPECT_NE(s.find("#SBATCH --partition=gpu\n"), std::string::npos) << s;
  // scene b is `paper`: every task gets paper's resources
  EXPECT_NE(s.find("#SBATCH --cpus-per-task=8\n"), std::string::npos) << s;
  EXPECT_NE(s.find("#SBATCH --mem=8G\n"), std::string::npos) << s;
  EXPECT_NE(s.find("exec '/opt/bin/photoscene' batch '" + (dir / "m.txt").string() + "' -o '" +
                   dir.path().string() + "' --task-index \"$SLURM_ARRAY_TASK_ID\""),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("--preset fast --texture-size 16"), std::string::npos) << s;
  const std::string onlyA = batch::slurmScript(b, {0}, {}, "/opt/bin/photoscene");
  EXPECT_NE(onlyA.find("#SBATCH --array=0\n"), std::string::npos) << onlyA;
  EXPECT_NE(onlyA.find("#SBATCH --cpus-per-task=2\n"), std::string::npos) << onlyA;
  EXPECT_EQ(onlyA.find("--partition"), std::string::npos) << onlyA;

  // the per-scene command: the scene's own preset wins over the batch's
  const auto args = batch::runArguments(b, 1, 3);
  const std::vector<std::string> expected = {
      "run",   "/data/b b/scene.json", "-o", (dir / "b").string(), "--preset",
      "paper", "--texture-size",       "16", "--threads",          "3"};
  EXPECT_EQ(args, expected);
}

}  // namespace
}  // namespace ps
