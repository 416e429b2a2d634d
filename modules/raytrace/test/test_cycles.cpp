// Against Blender Cycles as an independent reference: the ground-truth twins of the
// blender-room case rendered by `photoscene render`'s code path, compared with Cycles' renders.
//
// CI cost: Cycles rendered 640x480 at 1024 / 256 spp; here the twin is rendered at 160x120
// (the camera resized, same field of view) at 128 spp and Cycles' image is area-averaged to
// 160x120 (at 256 spp the three relative L1 figures were 0.0106 / 0.0310 / 0.0169, at 128 spp
// 0.0134 / 0.0319 / 0.0192: the bounds below are the model's gaps plus noise, not noise alone).
// Monte-Carlo noise of a low-spp render is then removed from the image metric by comparing
// 4x4-pixel box-filtered images (80x60 blocks); per-part means are taken over the part's pixels
// of our own G-buffer (eroded by one pixel so boundary pixels mixing two parts do not count).
// Environment variables (for local runs): PS_RT_CYCLES_DIV=1 renders 640x480 (default 4: 160x120),
// PS_RT_CYCLES_SPP overrides the spp, PS_RT_WRITE_DIR writes the renders and comparisons,
// PS_RT_PRINCIPLED_DIFFUSE=1 uses Burley diffuse (Blender's Principled v1) to measure that gap.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "photoscene/core/color.hpp"
#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;

fs::path caseDir() { return fs::path(PS_SHARED_DATA_DIR) / "examples" / "blender-room"; }

int envInt(const char* name, int def) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : def;
}

struct Comparison {
  double imageRelL1 = 0;        // sum |a - b| / sum b over the box-filtered images (all channels)
  double imageMeanRel = 0;      // mean over blocks of |lum a - lum b| / lum b (blocks with lum b > 0.01)
  double imageMeanRatio = 0;    // mean(a) / mean(b)
  double worstPartRel = 0;      // max over parts of |mean a - mean b| / mean b (luminance)
  std::string worstPart;
  std::string table;
};

inline double lum(const cv::Vec3f& c) {
  return luminance(double(c[0]), double(c[1]), double(c[2]));
}

Comparison compare(const cv::Mat& ours, const cv::Mat& ref, const GBuffer& gb, const Scene& scene, int block) {
  Comparison c;
  cv::Mat a, b;
  cv::resize(ours, a, cv::Size(ours.cols / block, ours.rows / block), 0, 0, cv::INTER_AREA);
  cv::resize(ref, b, a.size(), 0, 0, cv::INTER_AREA);
  double num = 0, den = 0, relSum = 0;
  int relN = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const cv::Vec3f pa = a.at<cv::Vec3f>(y, x), pb = b.at<cv::Vec3f>(y, x);
      for (int k = 0; k < 3; ++k) {
        num += std::abs(pa[k] - pb[k]);
        den += std::abs(pb[k]);
      }
      if (lum(pb) > 0.01) {
        relSum += std::abs(lum(pa) - lum(pb)) / lum(pb);
        ++relN;
      }
    }
  c.imageRelL1 = num / den;
  c.imageMeanRel = relSum / std::max(1, relN);
  const cv::Scalar ma = cv::mean(ours), mb = cv::mean(ref);
  c.imageMeanRatio = (ma[0] + ma[1] + ma[2]) / (mb[0] + mb[1] + mb[2]);
  std::ostringstream table;
  for (size_t p = 0; p < scene.parts.size(); ++p) {
    if (gb.mask[p].empty()) continue;
    cv::Mat inner;
    cv::erode(gb.mask[p], inner, cv::Mat::ones(3, 3, CV_8U));
    const int n = cv::countNonZero(inner);
    if (n < 50) continue;
    const cv::Scalar sa = cv::mean(ours, inner), sb = cv::mean(ref, inner);
    const double la = luminance(sa[0], sa[1], sa[2]), lb = luminance(sb[0], sb[1], sb[2]);
    const double rel = std::abs(la - lb) / std::max(lb, 1e-6);
    table << "  " << scene.parts[p].name << ": " << n << " px, ours " << la << ", cycles " << lb << ", rel "
          << rel << "\n";
    if (rel > c.worstPartRel) {
      c.worstPartRel = rel;
      c.worstPart = scene.parts[p].name;
    }
  }
  c.table = table.str();
  return c;
}

void writeComparison(const fs::path& dir, const std::string& name, const cv::Mat& ours, const cv::Mat& ref) {
  cv::Mat refS;
  cv::resize(ref, refS, ours.size(), 0, 0, cv::INTER_AREA);
  cv::Mat diff = cv::abs(ours - refS) * 4.0;
  cv::Mat row;
  cv::hconcat(std::vector<cv::Mat>{ours, refS, diff}, row);
  io::writeImage(dir / (name + "_ours_cycles_4xdiff.png"), row);
  io::writeImage(dir / (name + "_ours.exr"), ours);
}

struct CyclesCase {
  const char* twin;
  const char* reference;
  int spp;
  bool principledDiffuse = false;
};

Comparison runCase(const CyclesCase& cc, cv::Mat* oursOut = nullptr) {
  const Twin twin = loadTwin(caseDir() / "gt" / cc.twin);
  const PathTracer tracer(twin.scene, twin.materials);
  const int scale = std::max(1, envInt("PS_RT_CYCLES_DIV", 4));
  const Camera cam = twin.scene.views[0].camera.resized(640 / scale, 480 / scale);
  RenderOptions opt;
  opt.spp = envInt("PS_RT_CYCLES_SPP", cc.spp);
  opt.seed = 1;
  opt.principledDiffuse = cc.principledDiffuse || envInt("PS_RT_PRINCIPLED_DIFFUSE", 0) != 0;
  RenderStats stats;
  const cv::Mat ours = renderTwinView(tracer, cam, opt, twin.exposure[0], &stats);
  EXPECT_TRUE(allFinite(ours));
  const cv::Mat ref = io::readImage(caseDir() / "gt" / cc.reference);
  cv::Mat refS;
  cv::resize(ref, refS, ours.size(), 0, 0, cv::INTER_AREA);
  const GBuffer gb = renderGBuffer(tracer, cam, {1});
  const Comparison c = compare(ours, refS, gb, twin.scene, 4);
  std::printf("%s vs %s: %dx%d, %d spp, %.2fs, %.2f Mrays/s; relative L1 (4x4 blocks) %.4f, mean block rel %.4f, "
              "mean ratio %.4f, worst part %s %.4f\n%s",
              cc.twin, cc.reference, cam.width(), cam.height(), opt.spp, stats.seconds, stats.raysPerSecond() * 1e-6,
              c.imageRelL1, c.imageMeanRel, c.imageMeanRatio, c.worstPart.c_str(), c.worstPartRel, c.table.c_str());
  if (const char* dir = std::getenv("PS_RT_WRITE_DIR")) writeComparison(dir, cc.twin, ours, ref);
  if (oursOut) *oursOut = ours;
  return c;
}

TEST(Raytrace_Cycles, lambert_twin_matches_cycles) {
  if (!fs::exists(caseDir() / "gt" / "twin_lambert" / "scene.json")) GTEST_SKIP() << "blender-room case absent";
  const Comparison c = runCase({"twin_lambert", "lambert_view0.exr", 128});
  EXPECT_LT(c.imageRelL1, 0.02);
  EXPECT_LT(c.worstPartRel, 0.03) << c.worstPart;
  EXPECT_NEAR(c.imageMeanRatio, 1.0, 0.02);
}

TEST(Raytrace_Cycles, full_twin_matches_cycles) {
  if (!fs::exists(caseDir() / "gt" / "twin" / "scene.json")) GTEST_SKIP() << "blender-room case absent";
  const Comparison c = runCase({"twin", "view0.exr", 128});
  EXPECT_LT(c.imageRelL1, 0.05);
  EXPECT_NEAR(c.imageMeanRatio, 1.0, 0.05);
}

// What remains between the contract's model and Cycles' Principled BSDF is mostly its Burley
// (Disney) diffuse: with it (a measurement switch, not the contract's model) the ceiling's 20%
// and the wood's 7-10% gaps close to the level of the Lambert twin.
TEST(Raytrace_Cycles, full_twin_gap_is_principled_diffuse) {
  if (!fs::exists(caseDir() / "gt" / "twin" / "scene.json")) GTEST_SKIP() << "blender-room case absent";
  const Comparison c = runCase({"twin", "view0.exr", 128, true});
  EXPECT_LT(c.imageRelL1, 0.03);
  EXPECT_LT(c.worstPartRel, 0.04) << c.worstPart;
  EXPECT_NEAR(c.imageMeanRatio, 1.0, 0.025);
}

}  // namespace
}  // namespace ps
