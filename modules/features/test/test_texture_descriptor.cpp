#include "photoscene/core.hpp"
#include "photoscene/features.hpp"
#include "texture_fixtures.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace ps {
namespace {

using namespace test;  // texture_fixtures.hpp

std::vector<float> values(const cv::Mat& img, const cv::Mat& mask,
                          const TextureDescriptorOptions& o = {}) {
  return computeTextureDescriptor(img, mask, o).values;
}

double relKeyChange(const std::vector<float>& a, const std::vector<float>& b) {
  double n = 0.0;
  for (float v : a) n += double(v) * v;
  return descriptorDistance(a, b) / std::sqrt(n);
}

// Rescales about the center by `factor` (a texture seen 1.25x larger), keeping the size.
cv::Mat zoom(const cv::Mat& img, double factor) {
  cv::Mat big;
  cv::resize(img, big, cv::Size(), factor, factor, factor > 1 ? cv::INTER_CUBIC : cv::INTER_AREA);
  const cv::Rect r((big.cols - img.cols) / 2, (big.rows - img.rows) / 2, img.cols, img.rows);
  return big(r).clone();
}

TEST(Features_TextureDescriptor, layout_and_fixed_length) {
  TextureDescriptorOptions o;
  EXPECT_EQ(descriptorLength(o), 70);
  EXPECT_EQ(bandIndex(o, 0, 0), 6);
  EXPECT_EQ(bandIndex(o, 3, 3) + kBandStdMag, 69);
  TextureKeyOptions ko;
  EXPECT_EQ(keyLength(ko), 26);
  // Same length whatever the image and mask size.
  for (cv::Size size : {cv::Size(20, 10), cv::Size(320, 240), cv::Size(97, 301)}) {
    const cv::Mat img = noise(size, 1.0, 1);
    const cv::Mat mask = diskMask(size, {size.width / 2, size.height / 2}, size.height / 3);
    EXPECT_EQ(values(img, mask).size(), 70u);
    EXPECT_EQ(computeTextureKey(img, mask).size(), 26u);
  }
  o.numScales = 3;
  o.numOrientations = 6;
  EXPECT_EQ(descriptorLength(o), 6 + 4 * 18);
  const cv::Mat img = noise({64, 64}, 1.0, 1);
  EXPECT_EQ(values(img, diskMask({64, 64}, {32, 32}, 20), o).size(), 78u);
  std::string err;
  o.numScales = 0;
  EXPECT_FALSE(o.IsValid(&err));
  EXPECT_THROW(computeTextureDescriptor(img, diskMask({64, 64}, {32, 32}, 20), o), Exception);
  EXPECT_THROW(computeTextureDescriptor(img, cv::Mat::zeros(64, 64, CV_8UC1)), Exception);
  EXPECT_THROW(computeTextureDescriptor(img, cv::Mat::zeros(32, 64, CV_8UC1)), Exception);
}

// Pixels outside the mask and the amount of image around it change nothing: the region embedded
// in a larger canvas (at an offset aligned to the coarsest level) with another texture around it
// has the same descriptor.
TEST(Features_TextureDescriptor, outside_pixels_and_crop_do_not_matter) {
  const cv::Size size(100, 80);
  const cv::Mat img = noise(size, 1.5, 4);
  const cv::Mat mask = diskMask(size, {50, 40}, 35);
  cv::Mat canvas = checker({300, 200}, 3) * 5.0;
  cv::Mat canvasMask = cv::Mat::zeros(200, 300, CV_8UC1);
  const cv::Rect at(64, 40, size.width, size.height);
  img.copyTo(canvas(at), mask);
  mask.copyTo(canvasMask(at));
  const std::vector<float> a = values(img, mask), b = values(canvas, canvasMask);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-6 + 1e-5 * std::abs(a[i])) << i;
}

// Entries are in linear units: scaling the image scales the descriptor.
TEST(Features_TextureDescriptor, entries_scale_with_the_image) {
  const cv::Size size(120, 100);
  const cv::Mat img = stripes(size, 6.0, 30.0) + noise(size, 1.0, 2) * 0.2;
  const cv::Mat mask = diskMask(size, {60, 50}, 45);
  const std::vector<float> a = values(img, mask), b = values(img * 3.0, mask);
  for (size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(b[i], 3.0f * a[i], 1e-4 + 1e-4 * std::abs(b[i]));
}

// A grating's energy lands in the band tuned to it: period 8 = level 1, orientation by angle.
TEST(Features_TextureDescriptor, grating_energy_in_the_tuned_band) {
  const cv::Size size(160, 160);
  const cv::Mat mask = diskMask(size, {80, 80}, 70);
  TextureDescriptorOptions o;
  for (int k = 0; k < o.numOrientations; ++k) {
    const double angle = 180.0 * k / o.numOrientations;
    const std::vector<float> d = values(stripes(size, 8.0, angle, 0.0, {1, 1, 1}), mask);
    int best = -1;
    float bestE = -1;
    for (int s = 0; s < o.numScales; ++s)
      for (int j = 0; j < o.numOrientations; ++j) {
        const float e = d[bandIndex(o, s, j) + kBandMeanMag];
        if (e > bestE) bestE = e, best = s * o.numOrientations + j;
      }
    EXPECT_EQ(best, 1 * o.numOrientations + k) << "angle " << angle << " energy " << bestE;
    // Unit gain at the center frequency: amplitude 0.25 grating, |r| about 0.25.
    EXPECT_NEAR(bestE, 0.25f, 0.03f) << "angle " << angle;
  }
}

TEST(Features_TextureDescriptor, same_result_on_any_thread_count) {
  const cv::Mat img = noise({200, 150}, 1.2, 9);
  const cv::Mat mask = diskMask({200, 150}, {100, 75}, 60);
  std::vector<float> a, b;
  {
    ThreadLimit one(1);
    a = values(img, mask);
  }
  b = values(img, mask);
  EXPECT_EQ(a, b);
}

// Key: any positive per-channel scale of the image (lighting color and level) leaves it unchanged.
TEST(Features_TextureKey, invariant_to_lighting_color_and_level) {
  const cv::Size size(160, 120);
  const cv::Mat mask = diskMask(size, {80, 60}, 55);
  Rng rng(17);
  double worst = 0.0;
  for (const cv::Mat& tex :
       {noise(size, 1.5, 3), cv::Mat(stripes(size, 7.0, 30.0) + noise(size, 1, 4) * 0.1),
        checker(size, 6)}) {
    const std::vector<float> k0 = computeTextureKey(tex, mask);
    for (int i = 0; i < 6; ++i) {
      const float level = std::exp(rng.uniform(-3.0f, 3.0f));
      const cv::Vec3f color(rng.uniform(0.2f, 1.0f), rng.uniform(0.2f, 1.0f),
                            rng.uniform(0.2f, 1.0f));
      const std::vector<float> k1 = computeTextureKey(scaleChannels(tex, color * level), mask);
      worst = std::max(worst, relKeyChange(k0, k1));
    }
  }
  std::printf("[   info   ] key under lighting color x level: max relative change %.3g\n", worst);
  EXPECT_LT(worst, 1e-4);
}

struct Named {
  std::string name;
  std::function<cv::Mat(int variant)> make;  // variant: another crop / phase / seed
};

std::vector<Named> proceduralTextures(cv::Size size) {
  return {
      {"stripes fine 30deg", [=](int v) { return stripes(size, 5.0, 30.0, v * 1.3); }},
      {"stripes coarse 30deg", [=](int v) { return stripes(size, 14.0, 30.0, v * 1.3); }},
      {"checker 4",
       [=](int v) {
         return checker(size, 4, {v, 2 * v});
       }},
      {"checker 12",
       [=](int v) {
         return checker(size, 12, {3 * v, 5 * v});
       }},
      {"noise fine", [=](int v) { return noise(size, 1.0, 100 + v); }},
      {"noise coarse", [=](int v) { return noise(size, 4.0, 200 + v); }},
  };
}

// Same texture, another crop: close; different textures: far (keys and raw descriptors).
TEST(Features_TextureKey, discriminates_textures) {
  const cv::Size size(160, 160);
  const cv::Mat mask = diskMask(size, {80, 80}, 64);
  const auto textures = proceduralTextures(size);
  for (bool useKey : {true, false}) {
    std::vector<std::vector<std::vector<float>>> d(textures.size());
    for (size_t t = 0; t < textures.size(); ++t)
      for (int v = 0; v < 3; ++v) {
        const cv::Mat img = textures[t].make(v);
        d[t].push_back(useKey ? computeTextureKey(img, mask) : values(img, mask));
      }
    double maxSame = 0.0, minDiff = 1e30;
    std::string closest;
    for (size_t t = 0; t < d.size(); ++t)
      for (size_t u = 0; u < d.size(); ++u)
        for (int v = 0; v < 3; ++v)
          for (int w = 0; w < 3; ++w) {
            const double dist = descriptorDistance(d[t][v], d[u][w]);
            if (t == u && v != w) maxSame = std::max(maxSame, dist);
            if (t != u && dist < minDiff) {
              minDiff = dist;
              closest = textures[t].name + " / " + textures[u].name;
            }
          }
    std::printf(
        "[   info   ] %s: max same-texture distance %.4g, min different-texture %.4g "
        "(%s), margin %.1fx\n",
        useKey ? "key" : "descriptor", maxSame, minDiff, closest.c_str(), minDiff / maxSame);
    // The key is built for retrieval; the raw descriptor (the loss) also separates them, by less.
    EXPECT_GT(minDiff, (useKey ? 3.0 : 2.5) * maxSame) << closest;
  }
}

// Rotation by 90 degrees and scale by 1.25: the transformed texture's key is nearer its original
// than any other texture's key (also with a random lighting color and level on the query).
void expectRetrieval(const std::vector<std::string>& names, const std::vector<cv::Mat>& images,
                     const cv::Mat& mask, double minAccuracy, const char* what) {
  Rng rng(5);
  std::vector<std::vector<float>> bank;
  for (const cv::Mat& img : images) bank.push_back(computeTextureKey(img, mask));
  const std::vector<std::pair<std::string, std::function<cv::Mat(const cv::Mat&)>>> transforms = {
      {"rot90",
       [](const cv::Mat& m) {
         cv::Mat r;
         cv::rotate(m, r, cv::ROTATE_90_CLOCKWISE);
         return r;
       }},
      {"zoom1.25", [](const cv::Mat& m) { return zoom(m, 1.25); }},
      {"rot90+zoom1.25",
       [](const cv::Mat& m) {
         cv::Mat r;
         cv::rotate(m, r, cv::ROTATE_90_COUNTERCLOCKWISE);
         return zoom(r, 1.25);
       }},
  };
  for (const auto& [tname, transform] : transforms) {
    int correct = 0;
    double worstRatio = 1e30;
    std::string worst;
    for (size_t i = 0; i < images.size(); ++i) {
      const cv::Vec3f light =
          cv::Vec3f(rng.uniform(0.3f, 1.0f), rng.uniform(0.3f, 1.0f), rng.uniform(0.3f, 1.0f)) *
          std::exp(rng.uniform(-2.0f, 2.0f));
      const std::vector<float> q =
          computeTextureKey(scaleChannels(transform(images[i]), light), mask);
      const double self = descriptorDistance(q, bank[i]);
      double other = 1e30;
      size_t otherIdx = 0;
      for (size_t j = 0; j < images.size(); ++j) {
        if (j == i) continue;
        const double dj = descriptorDistance(q, bank[j]);
        if (dj < other) other = dj, otherIdx = j;
      }
      if (self < other) ++correct;
      if (other / self < worstRatio) {
        worstRatio = other / self;
        worst = names[i] + " (nearest other: " + names[otherIdx] + ")";
      }
    }
    const double accuracy = double(correct) / images.size();
    std::printf(
        "[   info   ] %s %s: %d/%zu retrieved, worst other/self distance ratio %.2f at %s\n", what,
        tname.c_str(), correct, images.size(), worstRatio, worst.c_str());
    EXPECT_GE(accuracy, minAccuracy) << what << " " << tname;
  }
}

TEST(Features_TextureKey, robust_to_rotation_and_scale_procedural) {
  const cv::Size size(192, 192);
  const cv::Mat mask = diskMask(size, {96, 96}, 72);
  std::vector<std::string> names;
  std::vector<cv::Mat> images;
  for (const Named& t : proceduralTextures(size)) {
    names.push_back(t.name);
    images.push_back(t.make(0));
  }
  expectRetrieval(names, images, mask, 1.0, "procedural");
}

TEST(Features_TextureKey, robust_to_rotation_and_scale_photographed) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (const char* dir : {"/textures/polyhaven", "/examples/blender-room/gt/textures"}) {
    const fs::path p = fs::path(PS_SHARED_DATA_DIR) / (std::string(dir).substr(1));
    if (!fs::is_directory(p)) continue;
    for (const auto& e : fs::directory_iterator(p)) {
      const std::string n = e.path().filename().string();
      if (n.find("_nor") != std::string::npos || n.find("_rough") != std::string::npos) continue;
      if (e.path().extension() != ".jpg" && e.path().extension() != ".png") continue;
      // The same texture can be in both folders: keep one copy of each name.
      if (std::none_of(files.begin(), files.end(),
                       [&](const fs::path& f) { return f.filename() == e.path().filename(); }))
        files.push_back(e.path());
    }
  }
  if (files.size() < 4)
    GTEST_SKIP() << "photographed textures not found under " << PS_SHARED_DATA_DIR;
  std::sort(files.begin(), files.end());
  const cv::Size size(192, 192);
  const cv::Mat mask = diskMask(size, {96, 96}, 72);
  std::vector<std::string> names;
  std::vector<cv::Mat> images;
  for (const fs::path& f : files) {
    cv::Mat bgr = cv::imread(f.string(), cv::IMREAD_COLOR);
    if (bgr.empty()) continue;
    cv::Mat rgb, small;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    // A quarter of the texture, at 192 x 192: about what a part of a 320 x 240 view shows.
    const cv::Rect quarter(0, 0, rgb.cols / 2, rgb.rows / 2);
    cv::resize(rgb(quarter), small, size, 0, 0, cv::INTER_AREA);
    names.push_back(f.filename().string());
    images.push_back(srgbToLinear(small));
  }
  expectRetrieval(names, images, mask, 1.0, "photographed");
}

// A thin strip (24 px: two periods of the coarsest texture, 1/8 of the blob's width), a ring and a
// blob of the same texture stay nearer each other than different
// textures under the same mask: the mask's shape does not dominate.
TEST(Features_TextureKey, robust_to_mask_shape) {
  const cv::Size size(200, 200);
  cv::Mat blob = diskMask(size, {100, 100}, 80);
  cv::Mat ring = blob.clone();
  cv::circle(ring, {100, 100}, 55, cv::Scalar(0), cv::FILLED);
  cv::Mat strip = cv::Mat::zeros(size, CV_8UC1);
  cv::rectangle(strip, cv::Rect(10, 88, 180, 24), cv::Scalar(255), cv::FILLED);
  const auto textures = proceduralTextures(size);
  for (const cv::Mat& shape : {ring, strip}) {
    for (size_t t = 0; t < textures.size(); ++t) {
      const cv::Mat img = textures[t].make(0);
      const double self =
          descriptorDistance(computeTextureKey(img, shape), computeTextureKey(img, blob));
      double other = 1e30;
      for (size_t u = 0; u < textures.size(); ++u) {
        if (u == t) continue;
        other = std::min(other, descriptorDistance(computeTextureKey(img, shape),
                                                   computeTextureKey(textures[u].make(0), shape)));
      }
      EXPECT_LT(self, other) << textures[t].name << (shape.data == strip.data ? " strip" : " ring");
    }
  }
}

// Degenerate masks and images give finite keys and descriptors.
TEST(Features_TextureKey, stress_stays_finite) {
  const cv::Size size(48, 40);
  cv::Mat one = cv::Mat::zeros(size, CV_8UC1);
  one.at<uint8_t>(39, 47) = 255;
  cv::Mat full(size, CV_8UC1, cv::Scalar(255));
  const cv::Mat black = cv::Mat::zeros(size, CV_32FC3);
  cv::Mat redOnly = cv::Mat::zeros(size, CV_32FC3);
  redOnly.setTo(cv::Scalar(1e4, 0, 0));
  const cv::Mat tex = noise(size, 1.0, 8);
  for (const cv::Mat& mask : {one, full})
    for (const cv::Mat& img : {black, redOnly, tex}) {
      const std::vector<float> k = computeTextureKey(img, mask);
      EXPECT_TRUE(allFinite(cv::Mat(k)));
      EXPECT_TRUE(allFinite(cv::Mat(values(img, mask))));
    }
}

}  // namespace
}  // namespace ps
