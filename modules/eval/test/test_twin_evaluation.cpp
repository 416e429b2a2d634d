#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "photoscene/eval.hpp"
#include "photoscene/io.hpp"

namespace ps::eval {
namespace {

namespace fs = std::filesystem;

TEST(Eval_Metrics, ssim_of_constant_images_is_the_luminance_term) {
  // Constant images have zero variance: SSIM = (2 a b + C1) / (a^2 + b^2 + C1), C1 = (0.01 L)^2.
  const cv::Mat a(16, 16, CV_32FC3, cv::Scalar::all(0.25)),
      b(16, 16, CV_32FC3, cv::Scalar::all(0.35));
  const double c1 = 1e-4;
  EXPECT_NEAR(ssim(a, b, ColorSpace::Linear),
              (2 * 0.25 * 0.35 + c1) / (0.25 * 0.25 + 0.35 * 0.35 + c1), 1e-5);
}

TwinEvaluation someEvaluation() {
  TwinEvaluation e;
  ViewScore v;
  v.view = 0;
  v.image = "photos/view0.png";
  v.score.srgb255 = {ColorSpace::Srgb255, 3.0, 38.6, 0.9, 0.05};
  v.score.linear = {ColorSpace::Linear, 0.01, std::numeric_limits<double>::infinity(), 0.95, 0.04};
  e.views.push_back(v);
  e.parts.push_back({"floor", 0, 1234, 2.5, std::numeric_limits<double>::quiet_NaN()});
  e.novel.push_back({"novel0", v.score});
  e.preset = "balanced";
  return e;
}

TEST(Eval_TwinEvaluation, metrics_json_has_the_schema_writes_null_for_non_finite_and_keeps_stages) {
  io::TempDir dir;
  writeMetricsJson(dir.path(), someEvaluation(), {{"geometry", 1.5}, {"select", 2.0}}, "fast");
  nlohmann::json j = io::readJsonFile(dir / "metrics.json");
  EXPECT_TRUE(j["color_spaces"]["srgb255"].is_string());
  EXPECT_TRUE(j["color_spaces"]["linear"].is_string());
  EXPECT_EQ(j["views"][0]["view"], 0);
  EXPECT_EQ(j["views"][0]["image"], "photos/view0.png");
  EXPECT_DOUBLE_EQ(j["views"][0]["srgb255"]["rmse"].get<double>(), 3.0);
  EXPECT_TRUE(j["views"][0]["linear"]["psnr"].is_null());
  EXPECT_EQ(j["parts"]["floor"]["pixels"], 1234);
  EXPECT_EQ(j["parts"]["floor"]["view"], 0);
  EXPECT_DOUBLE_EQ(j["parts"]["floor"]["srgb255"]["rmse"].get<double>(), 2.5);
  EXPECT_TRUE(j["parts"]["floor"]["linear"]["rmse"].is_null());
  EXPECT_EQ(j["novel"][0]["name"], "novel0");
  EXPECT_TRUE(j["relit"].is_array() && j["relit"].empty());
  EXPECT_DOUBLE_EQ(j["stages"]["select"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["total_seconds"].get<double>(), 3.5);
  EXPECT_EQ(j["preset"], "fast");
  // `photoscene eval` rewrites the metrics without stages: stages, total, preset and other keys
  // stay.
  j["method"] = "pixel-median";
  io::writeJsonFile(dir / "metrics.json", j);
  writeMetricsJson(dir.path(), someEvaluation());
  const nlohmann::json k = io::readJsonFile(dir / "metrics.json");
  EXPECT_DOUBLE_EQ(k["stages"]["geometry"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(k["total_seconds"].get<double>(), 3.5);
  EXPECT_EQ(k["preset"], "fast");
  EXPECT_EQ(k["method"], "pixel-median");
}

constexpr const char* kLights =
    R"({"emitters": [{"name": "l", "type": "area", "center": [0, 2, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1],
                      "radiance": [1, 1, 1]}], "exposure": [1]})";

TEST(Eval_TwinEvaluation, ground_truth_is_found_in_both_case_layouts) {
  io::TempDir dir;
  fs::create_directories(dir / "gt" / "twin");
  fs::create_directories(dir / "cameras");
  for (const char* f : {"gt/novel0.exr", "gt/novel0.png", "gt/novel1.png", "gt/relit0.exr",
                        "gt/view0.exr", "cameras/novel0.json"})
    std::ofstream(dir / f) << "x";
  // novel1 has no camera; relit0's lights come from gt/twin (the case's own file is another form)
  std::ofstream(dir / "lights_relit.json")
      << R"({"area": [], "environment": {"radiance": [1, 1, 1]}})";
  std::ofstream(dir / "gt" / "twin" / "lights_relit.json") << kLights;
  std::ofstream(dir / "gt" / "twin" / "lights.json") << kLights;
  std::vector<std::string> notes;
  const auto gt = findGroundTruth(dir.path(), 1, &notes);
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_EQ(gt[0].name, "novel0");
  EXPECT_EQ(gt[0].image.filename(), "novel0.exr");  // EXR before PNG
  ASSERT_TRUE(gt[0].camera.has_value());
  EXPECT_EQ(gt[1].name, "relit0");
  EXPECT_EQ(gt[1].kind, GroundTruthRender::Kind::Relit);
  ASSERT_TRUE(gt[1].lights && gt[1].photoLights);
  EXPECT_EQ(*gt[1].lights, dir / "gt" / "twin" / "lights_relit.json");
  EXPECT_EQ(*gt[1].photoLights, dir / "gt" / "twin" / "lights.json");
  EXPECT_FALSE(gt[1].camera.has_value());
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("novel1"), std::string::npos);
  EXPECT_TRUE(findGroundTruth(dir / "nowhere", 1).empty());
}

}  // namespace
}  // namespace ps::eval
