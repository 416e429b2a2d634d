// A photo coded in integers clips at 1 (homogeneous_fit.hpp): the closed-form fits match the
// mean of the render clipped where the photo clips. On a part whose render of the true material
// passes the clip level on many pixels of one channel, the albedo comes back within 1 % of the
// truth with the clip given, and well below it without (the test can fail); unclipped channels
// and photos with nothing clipped are unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "photoscene/optim.hpp"
// the in-memory room of the render module's tests (test-only code, shared rather than copied)
#include "../../render/test/synthetic_room.hpp"

namespace ps {
namespace {

using namespace testroom;

constexpr float kRoughness = 0.6f;
const Vec3f kTruth(0.9f, 0.5f, 0.2f);

struct ClippedFloor {
  Room room;
  testroom::View view;
  PartGeometry geo;
  cv::Mat render;  ///< the render layer's image of the true material
  float clip = 0;  ///< the red channel's 60th percentile over the part: 40 % of it clips
  cv::Mat photo;   ///< render clipped at `clip` in every channel
};

ClippedFloor clippedFloor() {
  ClippedFloor c{makeRoom(64, 48), {}, {}, {}, 0, {}};
  const std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                          lambert("ceiling", 0.8f), lambert("box", 0.6f)};
  const PathTracer tracer(c.room.scene, mats);
  c.view = prepareView(tracer, c.room.camera, 8, 4, 11);
  const int part = c.room.floor;
  c.geo = preparePartGeometry(c.view.gbuffer, c.room.camera.position().cast<float>(), c.view.grid,
                              c.view.gbuffer.mask[part], part);
  RenderLayerParams p;
  p.geometry = &c.geo;
  p.roughnessValue = kRoughness;
  p.albedo = cv::Mat(4, 4, CV_32FC3, cv::Scalar(kTruth.x(), kTruth.y(), kTruth.z()));
  renderLayerForward(p);
  c.render = p.image.clone();
  std::vector<float> red;
  for (const cv::Point& q : c.geo.pixels) red.push_back(c.render.at<cv::Vec3f>(q)[0]);
  std::nth_element(red.begin(), red.begin() + red.size() * 6 / 10, red.end());
  c.clip = red[red.size() * 6 / 10];
  c.photo = cv::min(c.render, c.clip);
  return c;
}

TEST(Optim_HomogeneousClip, the_albedo_matches_a_clipped_photo_with_the_clip_given) {
  const ClippedFloor c = clippedFloor();
  ASSERT_GT(c.geo.size(), 300u);
  int clippedBlue = 0;
  for (const cv::Point& q : c.geo.pixels) clippedBlue += c.render.at<cv::Vec3f>(q)[2] >= c.clip;
  ASSERT_EQ(clippedBlue, 0) << "the case must leave blue unclipped";
  const HomogeneousFit with = fitHomogeneous({{&c.geo, c.photo, c.clip}}, {kRoughness});
  const HomogeneousFit without = fitHomogeneous({{&c.geo, c.photo}}, {kRoughness});
  std::printf("red albedo: truth %.3f, clip given %.4f, ignored %.4f\n", kTruth.x(), with.albedo.x(),
              without.albedo.x());
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(with.albedo[k] / kTruth[k], 1.0f, 0.01f) << "channel " << k;
  EXPECT_LT(without.albedo.x(), 0.95f * kTruth.x());  // the mean of a clipped photo reads dim
  EXPECT_NEAR(without.albedo.z(), with.albedo.z(), 1e-6f);  // blue never clips: the closed form
  EXPECT_FALSE(with.albedoClamped);

  // nothing clipped: the clip level changes nothing
  const HomogeneousFit free = fitHomogeneous({{&c.geo, c.render}}, {kRoughness});
  const HomogeneousFit high = fitHomogeneous({{&c.geo, c.render, 1e3f}}, {kRoughness});
  for (int k = 0; k < 3; ++k) EXPECT_EQ(free.albedo[k], high.albedo[k]);

  // a photo clipped everywhere (and one black) stays finite; the saturated one is flagged
  const cv::Mat hot(c.photo.size(), CV_32FC3, cv::Scalar::all(c.clip));
  const HomogeneousFit h = fitHomogeneous({{&c.geo, hot, c.clip}}, roughnessGrid(3));
  EXPECT_TRUE(h.albedo.allFinite());
  EXPECT_LE(h.albedo.maxCoeff(), 1.0f);
  EXPECT_TRUE(h.albedoClamped);
  const HomogeneousFit b =
      fitHomogeneous({{&c.geo, cv::Mat::zeros(c.photo.size(), CV_32FC3), c.clip}}, roughnessGrid(3));
  EXPECT_TRUE(b.albedo.allFinite());
  EXPECT_TRUE(std::isfinite(b.loss));
}

TEST(Optim_HomogeneousClip, the_textured_refine_matches_a_clipped_photo_with_the_clip_given) {
  const ClippedFloor c = clippedFloor();
  // the map is the true albedo at half level: the refine's scale and offsets must bring it back
  const cv::Mat map(8, 8, CV_32FC3, cv::Scalar(0.5 * kTruth.x(), 0.5 * kTruth.y(), 0.5 * kTruth.z()));
  const cv::Mat normal(8, 8, CV_32FC3, cv::Scalar(0, 0, 1));
  const cv::Mat mask = c.view.gbuffer.mask[c.room.floor];
  const auto effective = [&](const TexturedRefine& r) {
    Vec3f a;
    for (int k = 0; k < 3; ++k) a[k] = r.albedoScale * (0.5f * kTruth[k] + r.albedoOffset[k]);
    return a;
  };
  const Vec3f with =
      effective(refineTextured(c.geo, c.photo, mask, map, normal, UvParams{}, kRoughness, 1, c.clip));
  const Vec3f without =
      effective(refineTextured(c.geo, c.photo, mask, map, normal, UvParams{}, kRoughness, 1));
  std::printf("red albedo: truth %.3f, clip given %.4f, ignored %.4f\n", kTruth.x(), with.x(),
              without.x());
  EXPECT_NEAR(with.x() / kTruth.x(), 1.0f, 0.02f);
  EXPECT_LT(without.x(), 0.95f * kTruth.x());
  for (int k : {1, 2}) EXPECT_NEAR(with[k], without[k], 1e-5f) << "channel " << k;
  // a black photo with a clip stays finite
  const TexturedRefine b = refineTextured(c.geo, cv::Mat::zeros(c.photo.size(), CV_32FC3), mask,
                                          map, normal, UvParams{}, kRoughness, 3, c.clip);
  EXPECT_TRUE(std::isfinite(b.loss));
  EXPECT_TRUE(std::isfinite(b.albedoScale));
}

}  // namespace
}  // namespace ps
