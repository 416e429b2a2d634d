// The coarse view of a part (downsamplePartGeometry) renders what the fine view shows, averaged:
// the layer's image of the downsampled geometry matches the 2 x 2 box average of the fine image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "synthetic_room.hpp"

namespace ps {
namespace {

using namespace testroom;

// a periodic pattern with detail at several scales (stripes, as the wood graphs have)
cv::Mat stripes(int n) {
  cv::Mat m(n, n, CV_32FC3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const float u = (x + 0.5f) / n, v = (y + 0.5f) / n;
      const float s = std::sin(2 * kPi * 4 * u) + 0.5f * std::sin(2 * kPi * (16 * u + 2 * v));
      m.at<cv::Vec3f>(y, x) = cv::Vec3f(0.4f + 0.15f * s, 0.3f + 0.1f * s, 0.2f + 0.05f * s);
    }
  return m;
}

TEST(Render_Downsample, coarse_geometry_renders_the_box_average_of_the_fine_image) {
  const int W = 160, H = 120;
  Room room = makeRoom(W, H);
  std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f),
                                    lambert("ceiling", 0.8f), lambert("box", 0.5f)};
  const PathTracer tracer(room.scene, mats);
  const testroom::View view = prepareView(tracer, room.camera, 8, 4, 3);
  const PartGeometry fine =
      preparePartGeometry(view.gbuffer, room.camera.position().cast<float>(), view.grid,
                          view.gbuffer.mask[room.floor], room.floor);
  cv::Mat mask;
  const PartGeometry coarse = downsamplePartGeometry(fine, &mask);
  ASSERT_EQ(coarse.imageSize, cv::Size(W / 2, H / 2));
  ASSERT_EQ(cv::countNonZero(mask), coarse.size());
  // nearly every block of the (convex) floor is inside it; none outside
  EXPECT_GT(coarse.size(), fine.size() / 4 * 0.9);
  EXPECT_LE(coarse.size(), fine.size() / 4);
  for (int rot : {0, 35})
    for (float scale : {1.0f, 0.35f}) {
      RenderLayerParams p;
      p.albedo = stripes(128);
      p.roughnessValue = 0.5f;
      p.uv.rotation = radians(static_cast<float>(rot));
      p.uv.logScale = std::log(scale);
      p.uv.offset = Vec2f(0.1f, 0.3f);
      p.geometry = &fine;
      renderLayerForward(p);
      const cv::Mat avg = downsampleImage(coarse, p.image);
      p.geometry = &coarse;
      renderLayerForward(p);
      double num = 0, den = 0, sa = 0, sb = 0;
      for (const cv::Point& q : coarse.pixels) {
        const cv::Vec3f a = p.image.at<cv::Vec3f>(q), b = avg.at<cv::Vec3f>(q);
        for (int c = 0; c < 3; ++c)
          num += std::abs(a[c] - b[c]), den += b[c], sa += a[c], sb += b[c];
      }
      std::printf("rotation %d, scale %.2f: rel MAE %.4f, mean ratio %.4f over %d px\n", rot, scale,
                  num / den, sa / sb, coarse.size());
      EXPECT_LT(num / den, 0.05);
      EXPECT_NEAR(sa / sb, 1.0, 0.01);
    }
}

}  // namespace
}  // namespace ps
