// `photoscene batch` in local mode as a user runs it: several small scenes two at a time, a bad
// scene that is recorded and does not stop the others, the summary and index, a rerun that
// recomputes nothing, an interrupted batch that resumes, and bad manifests (exit 2).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "cli_run.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;
using io::TempDir;
using namespace cli_test;  // runPhotoscene, Result, contains (cli_run.hpp)

/// A small valid scene in `dir` (cli_test::writeTinyCase, the scene of tests/test_cli.cpp's
/// CliScene) with its photo's red channel at `shade`.
void writeTinyScene(const fs::path& dir, double shade) {
  const nlohmann::json json = cli_test::writeTinyCase(dir, shade);  // makes the folder
  std::ofstream(dir / "scene.json") << json.dump(1);
}

/// summary.csv as rows of fields (no quoted commas in the rows these tests read, but the error
/// column may be quoted: it is the last one and kept whole).
std::vector<std::vector<std::string>> readCsv(const fs::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    size_t start = 0;
    while (true) {
      if (start < line.size() && line[start] == '"') {
        f.push_back(line.substr(start));
        break;
      }
      const size_t comma = line.find(',', start);
      f.push_back(
          line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    rows.push_back(f);
  }
  return rows;
}

int column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t k = 0; k < header.size(); ++k)
    if (header[k] == name) return static_cast<int>(k);
  return -1;
}

nlohmann::json record(const fs::path& root, const std::string& name) {
  return io::readJsonFile(root / ".batch/status" / (name + ".json"));
}

int countOccurrences(const std::string& s, const std::string& part) {
  int n = 0;
  for (size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
  return n;
}

// Three small scenes two at a time, and one bad scene: the bad one is recorded as bad input (exit
// 2 for the batch), the others finish; summary.csv and index.html describe all four; a rerun of the
// same command recomputes nothing, and a rerun with another texture size recomputes only the
// export.
TEST(BatchCli, three_scenes_two_at_a_time_and_a_bad_scene_then_reruns_resume) {
  TempDir dir;
  for (const char* name : {"room-a", "room-b", "room-c"})
    writeTinyScene(dir / "scenes" / name, 0.4);
  fs::create_directories(dir / "scenes/broken");
  std::ofstream(dir / "scenes/broken/scene.json")
      << R"({"version": 1, "geometry": 5, "views": []})";
  std::ofstream(dir / "scenes/rooms.txt") << "# three rooms and a broken one\nroom-a/scene.json\n"
                                             "broken/scene.json   # geometry is a number\n"
                                             "room-b/scene.json\n\nroom-c/scene.json\n";
  const fs::path root = dir / "out";
  const std::string cmd = "batch " + (dir / "scenes/rooms.txt").string() + " -o " + root.string() +
                          " --jobs 2 --threads 2 --preset fast --texture-size 16";
  const Result r = runPhotoscene(cmd);
  ASSERT_EQ(r.exitCode, 2) << r.output;

  // records: three done, one bad input naming its file and key
  for (const char* name : {"room-a", "room-b", "room-c"}) {
    const nlohmann::json rec = record(root, name);
    EXPECT_EQ(rec["status"], "done") << name << "\n" << r.output;
    EXPECT_EQ(rec["exit_code"], 0) << name;
    EXPECT_TRUE(fs::exists(root / name / "metrics.json")) << name;
    EXPECT_TRUE(fs::exists(root / name / "report.html")) << name;
    // two at a time on two threads: each scene ran with one
    EXPECT_TRUE(contains(io::readTextFile(root / ".batch/logs" / (std::string(name) + ".log")),
                         "--threads 1"))
        << name;
  }
  const nlohmann::json bad = record(root, "broken");
  EXPECT_EQ(bad["status"], "bad-input");
  EXPECT_EQ(bad["exit_code"], 2);
  EXPECT_TRUE(contains(bad["error"], "broken/scene.json")) << bad["error"];
  EXPECT_TRUE(contains(bad["error"], "geometry")) << bad["error"];
  EXPECT_FALSE(fs::exists(root / "broken")) << "bad input must leave no output folder";
  // two at a time: the first two scenes ran at once (their intervals overlap)
  const nlohmann::json a = record(root, "room-a"), bb = record(root, "broken");
  EXPECT_LT(bb["started"].get<std::string>(), a["finished"].get<std::string>());

  // summary.csv: a header and one row per scene, in manifest order
  const auto rows = readCsv(root / "summary.csv");
  ASSERT_EQ(rows.size(), 5u);
  const auto& h = rows[0];
  ASSERT_GE(h.size(), 6u);
  EXPECT_EQ(std::vector<std::string>(h.begin(), h.begin() + 4),
            (std::vector<std::string>{"name", "status", "exit_code", "seconds"}));
  const int fit = column(h, "seconds_fit"), geometry = column(h, "seconds_geometry"),
            rmse = column(h, "view_rmse");
  ASSERT_GE(fit, 0);
  ASSERT_GE(geometry, 0);
  ASSERT_GE(rmse, 0);
  EXPECT_LT(geometry, fit) << "stages in pipeline order";
  const std::vector<std::string> names = {"room-a", "broken", "room-b", "room-c"};
  for (size_t k = 0; k < names.size(); ++k) {
    const auto& row = rows[k + 1];
    ASSERT_EQ(row.size(), h.size()) << names[k];
    EXPECT_EQ(row[0], names[k]);
    if (names[k] == "broken") {
      EXPECT_EQ(row[1], "bad-input");
      EXPECT_EQ(row[2], "2");
      EXPECT_EQ(row[fit], "");
      EXPECT_TRUE(contains(row.back(), "geometry")) << row.back();
    } else {
      EXPECT_EQ(row[1], "done");
      EXPECT_EQ(row[2], "0");
      EXPECT_GT(std::stod(row[3]), 0.0);
      EXPECT_GE(std::stod(row[fit]), 0.0);
      // the photo is one flat colour the twin can match: RMSE on the 0-255 scale, finite and small
      const double e = std::stod(row[rmse]);
      EXPECT_TRUE(e >= 0 && e < 60) << names[k] << " view_rmse " << e;
    }
  }
  // index.html links every report and every log
  const std::string index = io::readTextFile(root / "index.html");
  for (const char* name : {"room-a", "room-b", "room-c"})
    EXPECT_TRUE(contains(index, std::string("href=\"") + name + "/report.html\"")) << name;
  for (const std::string& name : names)
    EXPECT_TRUE(contains(index, ".batch/logs/" + name + ".log")) << name;
  EXPECT_TRUE(contains(index, "3 done, 0 failed, 1 bad input"));

  // --status reads the same (exit as the batch's)
  const Result st = runPhotoscene("batch --status " + root.string());
  EXPECT_EQ(st.exitCode, 2) << st.output;
  EXPECT_TRUE(std::regex_search(st.output, std::regex("broken +bad-input +2 .*geometry")))
      << st.output;

  // the same command again: done scenes are skipped (not run at all), the bad one is tried again
  const Result again = runPhotoscene(cmd);
  EXPECT_EQ(again.exitCode, 2) << again.output;
  EXPECT_EQ(countOccurrences(again.output, "done already, skipped"), 3) << again.output;
  for (const char* name : {"room-a", "room-b", "room-c"}) {
    EXPECT_EQ(record(root, name)["attempts"], 1) << name;
    EXPECT_EQ(
        countOccurrences(io::readTextFile(root / ".batch/logs" / (std::string(name) + ".log")),
                         "=== photoscene batch"),
        1);
  }
  EXPECT_EQ(record(root, "broken")["attempts"], 2);

  // another texture size: each scene runs again, and its stage cache leaves only the export's part
  const Result bigger =
      runPhotoscene("batch " + (dir / "scenes/rooms.txt").string() + " -o " + root.string() +
                    " --jobs 2 --threads 2 --preset fast --texture-size 32");
  EXPECT_EQ(bigger.exitCode, 2) << bigger.output;
  for (const char* name : {"room-a", "room-b", "room-c"}) {
    const std::string log = io::readTextFile(root / ".batch/logs" / (std::string(name) + ".log"));
    const std::string second = log.substr(log.rfind("=== photoscene batch"));
    EXPECT_TRUE(contains(second, "attempt 2")) << second;
    for (const char* stage : {"geometry", "align", "select", "fit", "refine"}) {
      std::smatch m;
      ASSERT_TRUE(std::regex_search(
          second, m, std::regex(std::string("\\n") + stage + R"(\s+[\d.]+\s+(\d+)\s+(\d+))")))
          << stage << "\n"
          << second;
      EXPECT_EQ(m[1], "0") << name << " recomputed " << stage << "\n" << second;
      EXPECT_NE(m[2], "0") << name << " " << stage << "\n" << second;
    }
    EXPECT_EQ(record(root, name)["status"], "done");
  }
}

// SIGINT to a local batch: the running scene stops at a check point, is recorded as pending, the
// batch exits 130; the rerun finishes it from its stage cache.
TEST(BatchCli, an_interrupted_batch_records_pending_and_the_rerun_finishes_from_the_cache) {
  TempDir dir;
  writeTinyScene(dir / "scenes/room", 0.5);
  std::ofstream(dir / "scenes/one.txt") << "room/scene.json\n";
  const fs::path root = dir / "out", marker = dir / "paused";
  const std::string manifest = (dir / "scenes/one.txt").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("PS_PAUSE_AT_STAGE", "fit", 1);
    setenv("PS_PAUSE_MARKER", marker.c_str(), 1);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    const std::string o = root.string();
    execl(PHOTOSCENE_BIN, PHOTOSCENE_BIN, "-q", "batch", manifest.c_str(), "-o", o.c_str(),
          "--preset", "fast", "--texture-size", "16", "--threads", "2",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  bool paused = false;
  for (int i = 0; i < 1200 && !paused; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    paused = fs::exists(marker);
  }
  if (!paused) kill(pid, SIGKILL);
  ASSERT_TRUE(paused) << "the scene did not reach its fit stage in 120 s";
  EXPECT_EQ(record(root, "room")["status"], "running");
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const nlohmann::json rec = record(root, "room");
  EXPECT_EQ(rec["status"], "pending");
  EXPECT_EQ(rec["exit_code"], 130);
  EXPECT_TRUE(contains(rec["error"], "interrupted")) << rec["error"];
  EXPECT_FALSE(fs::exists(root / "room/metrics.json"));
  for (const auto& e : fs::recursive_directory_iterator(root))
    EXPECT_FALSE(contains(e.path().filename().string(), ".tmp-")) << e.path();
  const auto rows = readCsv(root / "summary.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][1], "pending");

  const Result again = runPhotoscene("batch " + manifest + " -o " + root.string() +
                                     " --preset fast --texture-size 16 --threads 2");
  EXPECT_EQ(again.exitCode, 0) << again.output;
  EXPECT_EQ(record(root, "room")["status"], "done");
  const std::string log = io::readTextFile(root / ".batch/logs/room.log");
  const std::string second = log.substr(log.rfind("=== photoscene batch"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(second, m, std::regex(R"(\nalign\s+[\d.]+\s+(\d+)\s+(\d+))")))
      << second;
  EXPECT_EQ(m[1], "0") << "the rerun recomputed the alignment\n" << second;
}

// A scene that fails (not bad input): recorded as failed with its error line, the batch exits 1,
// --status shows the error; the rerun finishes it.
TEST(BatchCli, a_failed_scene_is_recorded_with_its_error_and_the_rerun_finishes_it) {
  TempDir dir;
  writeTinyScene(dir / "scenes/room", 0.45);
  std::ofstream(dir / "scenes/one.txt") << "room/scene.json\n";
  const fs::path root = dir / "out";
  const std::string cmd = "batch " + (dir / "scenes/one.txt").string() + " -o " + root.string() +
                          " --preset fast --texture-size 16 --threads 2";
  setenv("PS_FAIL_AT_STAGE", "export", 1);  // the children inherit it
  const Result failed = runPhotoscene(cmd);
  unsetenv("PS_FAIL_AT_STAGE");
  EXPECT_EQ(failed.exitCode, 1) << failed.output;
  const nlohmann::json rec = record(root, "room");
  EXPECT_EQ(rec["status"], "failed");
  EXPECT_EQ(rec["exit_code"], 1);
  EXPECT_TRUE(contains(rec["error"], "PS_FAIL_AT_STAGE=export")) << rec["error"];
  const Result st = runPhotoscene("batch --status " + root.string());
  EXPECT_EQ(st.exitCode, 1) << st.output;
  EXPECT_TRUE(std::regex_search(st.output, std::regex("room +failed +1 .*PS_FAIL_AT_STAGE=export")))
      << st.output;
  EXPECT_TRUE(contains(io::readTextFile(root / "summary.csv"), "room,failed,1,"))
      << io::readTextFile(root / "summary.csv");

  const Result again = runPhotoscene(cmd);
  EXPECT_EQ(again.exitCode, 0) << again.output;
  EXPECT_EQ(record(root, "room")["status"], "done");
  EXPECT_EQ(record(root, "room")["error"], "");
  EXPECT_TRUE(fs::exists(root / "room/metrics.json"));
}

TEST(BatchCli, bad_manifests_exit_2_naming_the_file_and_line_and_write_nothing) {
  TempDir dir;
  writeTinyScene(dir / "a", 0.4);
  fs::create_directories(dir / "x/a");
  std::ofstream(dir / "x/a/scene.json") << "{}";
  std::ofstream(dir / "dup.txt") << "a/scene.json\nx/a/scene.json\n";
  Result r = runPhotoscene("batch " + (dir / "dup.txt").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "dup.txt")) << r.output;
  EXPECT_TRUE(contains(r.output, "line 2")) << r.output;
  EXPECT_TRUE(contains(r.output, "unique")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));

  std::ofstream(dir / "m.json")
      << R"({"version": 1, "scenes": [{"scene": "a/scene.json", "options": {"preset": "slow"}}]})";
  r = runPhotoscene("batch " + (dir / "m.json").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "m.json")) << r.output;
  EXPECT_TRUE(contains(r.output, "scenes[0].options.preset")) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));

  r = runPhotoscene("batch " + (dir / "absent.txt").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "absent.txt")) << r.output;
  r = runPhotoscene("batch --status " + (dir / "a").string());
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "batch.json")) << r.output;
  r = runPhotoscene("batch " + (dir / "dup.txt").string());
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "-o")) << r.output;
}

}  // namespace
}  // namespace ps
