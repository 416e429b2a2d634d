// Runs every stage sample on the bundled sample scene (samples/data/living-room), as a newcomer
// would, and checks what each one claims.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "run_command.hpp"

namespace {

namespace fs = std::filesystem;

using Result = ps::cli_test::Result;
const auto run = ps::cli_test::runCommand;

const fs::path kSample = fs::path(PS_SAMPLE_DIR);
const fs::path kBin = fs::path(PS_BIN_DIR);

bool haveSample() { return fs::exists(kSample / "scene.json"); }

TEST(Samples, render_reproduces_the_photo_from_the_ground_truth_twin) {
  if (!haveSample() || !fs::exists(kBin / "ps_sample_render")) GTEST_SKIP() << "sample or program not built";
  ps::io::TempDir dir;
  const Result r = run((kBin / "ps_sample_render").string() + " " + (kSample / "gt/twin").string() + " " +
                       (dir / "render.exr").string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const cv::Mat render = ps::io::readImage(dir / "render.exr");
  const cv::Mat truth = ps::io::readImage(kSample / "gt/view0.exr");
  const cv::Scalar a = cv::mean(render), b = cv::mean(truth);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c] / b[c], 1.0, 0.05) << "channel " << c;
}

TEST(Samples, align_matches_every_pinned_region_and_aligns_it) {
  if (!haveSample() || !fs::exists(kBin / "ps_sample_align")) GTEST_SKIP() << "sample or program not built";
  ps::io::TempDir dir;
  const Result r = run((kBin / "ps_sample_align").string() + " " + (kSample / "scene.json").string() + " " +
                       dir.path().string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "aligned_masks.png"));
  // every part row: M_aln keeps most of M_photo (the coarse CAD is off by a few cm only)
  const std::regex row(R"((\w+)\s+(\d+)\s+(\d+)\s+([\d.]+)\s+(\d+)\s+(\d+))");
  int rows = 0;
  for (std::sregex_iterator it(r.output.begin(), r.output.end(), row), end; it != end; ++it) {
    const int photo = std::stoi((*it)[3]), aligned = std::stoi((*it)[5]);
    if (photo < 500) continue;  // thin parts (table legs) may lose more at the boundary
    ++rows;
    EXPECT_GT(aligned, 0.8 * photo) << (*it)[1];
  }
  EXPECT_GE(rows, 6) << r.output;
}

TEST(Samples, light_fit_explains_the_photo) {
  if (!haveSample() || !fs::exists(kBin / "ps_sample_light")) GTEST_SKIP() << "sample or program not built";
  const Result r = run((kBin / "ps_sample_light").string() + " " + (kSample / "scene.json").string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(residual rms ([\d.]+) of photo rms ([\d.]+))"))) << r.output;
  EXPECT_LT(std::stod(m[1]), 0.5 * std::stod(m[2])) << r.output;
  EXPECT_EQ(r.output.find("dropped"), std::string::npos) << r.output;  // both lights light the room
}

TEST(Samples, select_gives_every_part_a_graph) {
  if (!haveSample() || !fs::exists(kBin / "ps_sample_select")) GTEST_SKIP() << "sample or program not built";
  // the build tree's shared bank cache (built once per test run, whichever test comes first)
  const fs::path cache = kBin.parent_path() / "photoscene-cache";
  const Result r = run((kBin / "ps_sample_select").string() + " " + (kSample / "scene.json").string() + " " +
                       cache.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("floor"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("exemplar bank"), std::string::npos) << r.output;
  // a second run loads the cached bank
  const Result again = run((kBin / "ps_sample_select").string() + " " + (kSample / "scene.json").string() + " " +
                           cache.string());
  EXPECT_NE(again.output.find("loaded"), std::string::npos) << again.output;
}

TEST(Samples, fit_part_lowers_the_loss_on_the_floor) {
  if (!haveSample() || !fs::exists(kBin / "ps_sample_fit_part")) GTEST_SKIP() << "sample or program not built";
  ps::io::TempDir out;
  const Result r = run((kBin / "ps_sample_fit_part").string() + " " + (kSample / "scene.json").string() + " " +
                       (kSample / "gt/twin/lights.json").string() + " floor wood_planks " +
                       (out.path() / "fit.png").string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(loss ([\d.]+) -> ([\d.]+))"))) << r.output;
  EXPECT_LT(std::stod(m[2]), 0.5 * std::stod(m[1])) << r.output;
  EXPECT_TRUE(fs::exists(out.path() / "fit.png"));
}

}  // namespace
