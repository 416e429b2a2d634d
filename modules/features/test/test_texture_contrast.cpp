// Typical local contrast: fine structure almost everywhere (texture) against a few strong edges
// (a plain surface with objects in its mask), independent of the light's level and of smooth
// shading; finite on black, saturated, non-finite and tiny inputs.
#include "photoscene/core/error.hpp"
#include "photoscene/features.hpp"
#include "texture_fixtures.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>

namespace ps {
namespace {

using test::checker;
using test::diskMask;
using test::noise;

const cv::Size kSize(160, 120);

cv::Mat flat(float v = 0.4f) { return cv::Mat(kSize, CV_32FC3, cv::Scalar::all(v)); }

TEST(Features_Contrast, a_texture_has_contrast_almost_everywhere_a_plain_surface_with_edges_not) {
  const cv::Mat mask = diskMask(kSize, {80, 60}, 55);
  // plain plaster: faint fine noise
  cv::Mat plain = flat() + (noise(kSize, 1.0, 3) - flat()) * 0.05;
  // the same wall with a picture frame and a shelf in the mask: strong edges on few pixels
  cv::Mat cluttered = plain.clone();
  cv::rectangle(cluttered, cv::Rect(40, 30, 30, 24), cv::Scalar::all(0.05), 2);
  cv::rectangle(cluttered, cv::Rect(60, 80, 60, 4), cv::Scalar::all(0.9), cv::FILLED);
  // tiles: a checker of 6 px cells, and a grainy texture
  const cv::Mat tiles = checker(kSize, 6), grain = noise(kSize, 1.0, 7);
  const LocalContrast p = typicalLocalContrast(plain, mask);
  const LocalContrast c = typicalLocalContrast(cluttered, mask);
  const LocalContrast t = typicalLocalContrast(tiles, mask);
  const LocalContrast g = typicalLocalContrast(grain, mask);
  std::printf("median local contrast: plain %.4f, cluttered %.4f, tiles %.4f, grain %.4f\n",
              p.median, c.median, t.median, g.median);
  EXPECT_GT(p.pixels, 8000);
  // the clutter's edges move the median little; both textures sit far above
  EXPECT_LT(c.median, 1.5 * p.median);
  EXPECT_GT(t.median, 5 * c.median);
  EXPECT_GT(g.median, 5 * c.median);
  // while the clutter moves the mean subband energy as a texture would: its variance over the
  // mask is of the texture's order
  cv::Scalar mc, sc, mp, sp;
  cv::meanStdDev(cluttered, mc, sc, mask);
  cv::meanStdDev(plain, mp, sp, mask);
  EXPECT_GT(sc[0], 5 * sp[0]);
  EXPECT_LE(p.q25, p.median);
  EXPECT_LE(p.median, p.q75);
}

TEST(Features_Contrast, the_lights_level_and_smooth_shading_do_not_matter) {
  const cv::Mat mask = diskMask(kSize, {80, 60}, 55);
  const cv::Mat grain = noise(kSize, 1.5, 11);
  const double base = typicalLocalContrast(grain, mask).median;
  EXPECT_NEAR(typicalLocalContrast(grain * 7.0, mask).median, base, 1e-4 * base);
  // a falloff across the part (0.4 to 1.6: a lamp near one end)
  cv::Mat shaded = grain.clone();
  for (int y = 0; y < kSize.height; ++y)
    for (int x = 0; x < kSize.width; ++x) shaded.at<cv::Vec3f>(y, x) *= 0.4f + 1.2f * x / kSize.width;
  EXPECT_NEAR(typicalLocalContrast(shaded, mask).median, base, 0.05 * base);
}

TEST(Features_Contrast, at_a_coarser_scale_fine_grain_averages_away_and_blotches_stay) {
  // sand-like grain (noise blurred by 0.7 px) and blotches (4 px) of one global spread: over 2 x 2
  // cell means the grain loses local contrast and the blotches gain it (the window now spans
  // them). What the selection's coarse test tells apart: a photo of fine grain and a render of
  // coarse blotches, which may have the same contrast at full resolution.
  const cv::Mat mask = diskMask(kSize, {80, 60}, 55);
  const cv::Mat grain = noise(kSize, 0.7, 13), blotches = noise(kSize, 4.0, 13);
  LocalContrastOptions coarse;
  coarse.scale = 2;
  const LocalContrast g1 = typicalLocalContrast(grain, mask),
                      g2 = typicalLocalContrast(grain, mask, coarse);
  const LocalContrast b1 = typicalLocalContrast(blotches, mask),
                      b2 = typicalLocalContrast(blotches, mask, coarse);
  std::printf("grain %.4f -> %.4f, blotches %.4f -> %.4f (scale 1 -> 2)\n", g1.median, g2.median,
              b1.median, b2.median);
  EXPECT_LT(g2.median, g1.median);
  EXPECT_GT(b2.median, b1.median);
  EXPECT_GT(b2.median / b1.median, 1.5 * (g2.median / g1.median));
  // the cells whose 5 x 5 window lies in the disk: about a quarter of the pixels' count, less
  // the wider border band a window of cells leaves
  std::printf("counted: %d pixels, %d cells\n", g1.pixels, g2.pixels);
  EXPECT_GT(g2.pixels, g1.pixels / 5);
  EXPECT_LT(g2.pixels, g1.pixels / 4);
  // invariant to the light's level at any scale
  EXPECT_NEAR(typicalLocalContrast(blotches * 5.0, mask, coarse).median, b2.median, 1e-4 * b2.median);
  // a mask no cell lies wholly in (a one-pixel-wide line), an image smaller than a cell
  cv::Mat line = cv::Mat::zeros(kSize, CV_8UC1);
  line.col(80).setTo(255);
  EXPECT_EQ(typicalLocalContrast(grain, line, coarse).pixels, 0);
  const cv::Mat tiny = noise({1, 1}, 0.7, 1);
  const LocalContrast t = typicalLocalContrast(tiny, cv::Mat(1, 1, CV_8UC1, cv::Scalar(255)), coarse);
  EXPECT_EQ(t.pixels, 0);
  EXPECT_EQ(t.median, 0.0);
  coarse.scale = 0;
  EXPECT_THROW(typicalLocalContrast(grain, mask, coarse), Exception);
}

TEST(Features_Contrast, finite_on_black_saturated_non_finite_and_tiny_regions) {
  const cv::Mat mask = diskMask(kSize, {80, 60}, 55);
  const LocalContrast black = typicalLocalContrast(flat(0.0f), mask);
  EXPECT_EQ(black.median, 0.0);
  EXPECT_GT(black.pixels, 0);
  // half black, half bright: the dark floor keeps the ratio bounded
  cv::Mat half = flat(0.0f);
  half(cv::Rect(80, 0, 80, kSize.height)).setTo(cv::Scalar::all(1e4));
  const LocalContrast h = typicalLocalContrast(half, mask);
  EXPECT_TRUE(std::isfinite(h.median) && std::isfinite(h.q75));
  cv::Mat bad = noise(kSize, 1.0, 5);
  bad.at<cv::Vec3f>(60, 80) = cv::Vec3f(std::numeric_limits<float>::quiet_NaN(),
                                        std::numeric_limits<float>::infinity(), -1.0f);
  EXPECT_TRUE(std::isfinite(typicalLocalContrast(bad, mask).median));
  // one pixel, a line thinner than the window, an empty mask: no pixel counts
  cv::Mat one = cv::Mat::zeros(kSize, CV_8UC1), line = one.clone();
  one.at<uint8_t>(60, 80) = 255;
  line.row(60).setTo(255);
  for (const cv::Mat& m : {one, line, cv::Mat(cv::Mat::zeros(kSize, CV_8UC1))}) {
    const LocalContrast c = typicalLocalContrast(bad, m);
    EXPECT_EQ(c.pixels, 0);
    EXPECT_EQ(c.median, 0.0);
  }
  EXPECT_THROW(typicalLocalContrast(cv::Mat(kSize, CV_32FC1), mask), Exception);
}

TEST(Features_Contrast, chroma_spread_counts_colours_whatever_the_lights_colour) {
  const cv::Mat mask = diskMask(kSize, {80, 60}, 55);
  // a white surface with fine grain (a painted chair, a fridge) and a small red tag on it
  cv::Mat white = flat(0.7f) + (noise(kSize, 1.0, 21) - flat()) * 0.1;
  cv::rectangle(white, cv::Rect(70, 50, 6, 8), cv::Scalar(0.6, 0.05, 0.05), cv::FILLED);
  // blue and orange tiles of the same mean level
  cv::Mat tiles(kSize, CV_32FC3);
  for (int y = 0; y < kSize.height; ++y)
    for (int x = 0; x < kSize.width; ++x)
      tiles.at<cv::Vec3f>(y, x) =
          ((x / 8 + y / 8) & 1) ? cv::Vec3f(0.8f, 0.45f, 0.15f) : cv::Vec3f(0.15f, 0.35f, 0.7f);
  const ChromaSpread w = chromaSpread(white, mask), t = chromaSpread(tiles, mask);
  std::printf("chroma spread: white with a tag %.4f, blue and orange tiles %.4f\n", w.spread,
              t.spread);
  EXPECT_GT(w.pixels, 8000);
  EXPECT_LT(w.spread, 0.05);  // the tag is under a tenth of the pixels: the 10-90 range skips it
  EXPECT_GT(t.spread, 2.0);   // log(0.8 / 0.45) - log(0.15 / 0.35), and more in blue
  // a warm light (per-channel scale) and another level move every log chromaticity alike
  cv::Mat warm;
  cv::multiply(tiles, cv::Scalar(1.6, 1.0, 0.5), warm);
  EXPECT_NEAR(chromaSpread(warm * 3.0, mask).spread, t.spread, 0.02 * t.spread);
  // black, non-finite and negative pixels, an empty mask: finite, nothing counted from them
  cv::Mat bad = tiles.clone();
  bad.at<cv::Vec3f>(60, 80) = cv::Vec3f(std::numeric_limits<float>::quiet_NaN(),
                                        std::numeric_limits<float>::infinity(), -1.0f);
  EXPECT_TRUE(std::isfinite(chromaSpread(bad, mask).spread));
  EXPECT_EQ(chromaSpread(flat(0.0f), mask).pixels, 0);
  EXPECT_EQ(chromaSpread(tiles, cv::Mat(cv::Mat::zeros(kSize, CV_8UC1))).pixels, 0);
  cv::Mat one = cv::Mat::zeros(kSize, CV_8UC1);
  one.at<uint8_t>(60, 80) = 255;
  const ChromaSpread o = chromaSpread(tiles, one);
  EXPECT_EQ(o.pixels, 1);
  EXPECT_EQ(o.spread, 0.0);
  EXPECT_THROW(chromaSpread(cv::Mat(kSize, CV_32FC1), mask), Exception);
}

TEST(Features_Contrast, chroma_gamut_tells_which_colours_not_only_how_many) {
  const cv::Mat mask = diskMask(kSize, {80, 60}, 55);
  const int n = cv::countNonZero(mask);
  // the photo: a white chair with grain whose mask also holds warm wood (the floor between its
  // legs) on a quarter of its pixels: a wide spread, all of it along white -> brown
  cv::Mat photo = flat(0.7f) + (noise(kSize, 1.0, 21) - flat()) * 0.1;
  cv::rectangle(photo, cv::Rect(20, 80, 120, 40), cv::Scalar(0.45, 0.28, 0.14), cv::FILLED);
  // renders of the same mean level: white and wood planks (the photo's colours), and white
  // with pale teal stripes on a fifth of the pixels (a colour the photo does not show)
  cv::Mat planks = flat(0.7f), teal = flat(0.7f);
  for (int x = 0; x < kSize.width; x += 10) {
    cv::rectangle(planks, cv::Rect(x, 0, 3, kSize.height), cv::Scalar(0.45, 0.28, 0.14),
                  cv::FILLED);
    cv::rectangle(teal, cv::Rect(x, 0, 2, kSize.height), cv::Scalar(0.5, 0.7, 0.68), cv::FILLED);
  }
  const ChromaGamut g = chromaGamut(photo, mask);
  EXPECT_GT(g.pixels, n / 2);
  const double fromPhoto = chromaOutside(g, photo, mask),
               fromPlanks = chromaOutside(g, planks, mask), fromTeal = chromaOutside(g, teal, mask),
               fromFlat = chromaOutside(g, flat(0.6f), mask);
  std::printf(
      "outside the photo's colours: itself %.3f, planks %.3f, teal stripes %.3f, flat %.3f\n",
      fromPhoto, fromPlanks, fromTeal, fromFlat);
  EXPECT_EQ(fromPhoto, 0.0);  // every pixel's bin holds it and at least one more, or a neighbour
  EXPECT_LT(fromPlanks, 0.02);
  EXPECT_EQ(fromFlat, 0.0);
  EXPECT_NEAR(fromTeal, 0.2, 0.03);  // the stripes' share, 2 of every 10 columns
  // the spread alone lets the pale teal through: it is below the photo's
  EXPECT_LT(chromaSpread(teal, mask).spread, chromaSpread(photo, mask).spread);
  // a warm light on the render, or on the photo, and another level: the same verdict
  cv::Mat warmTeal, warmPhoto;
  cv::multiply(teal, cv::Scalar(1.6, 1.0, 0.5), warmTeal);
  cv::multiply(photo, cv::Scalar(0.7, 1.0, 1.4), warmPhoto);
  EXPECT_NEAR(chromaOutside(g, warmTeal * 3.0, mask), fromTeal, 0.01);
  EXPECT_NEAR(chromaOutside(chromaGamut(warmPhoto * 0.2, mask), teal, mask), fromTeal, 0.01);
  // a lone pixel of a colour is no colour the photo shows
  cv::Mat speck = flat(0.7f);
  speck.at<cv::Vec3f>(60, 80) = cv::Vec3f(0.1f, 0.45f, 0.42f);
  cv::Mat tealPatch = flat(0.7f);
  cv::rectangle(tealPatch, cv::Rect(60, 40, 40, 40), cv::Scalar(0.1, 0.45, 0.42), cv::FILLED);
  EXPECT_NEAR(chromaOutside(chromaGamut(speck, mask), tealPatch, mask), 1600.0 / n, 0.01);
  // black, non-finite and negative pixels, an empty or one-pixel mask: finite, in [0, 1]
  cv::Mat bad = teal.clone();
  bad.at<cv::Vec3f>(60, 80) = cv::Vec3f(std::numeric_limits<float>::quiet_NaN(),
                                        std::numeric_limits<float>::infinity(), -1.0f);
  const double b = chromaOutside(chromaGamut(bad, mask), bad, mask);
  EXPECT_TRUE(b >= 0 && b <= 1);
  const cv::Mat none = cv::Mat::zeros(kSize, CV_8UC1);
  EXPECT_TRUE(chromaGamut(photo, none).bins.empty());
  EXPECT_EQ(chromaOutside(g, teal, none), 0.0);
  EXPECT_EQ(chromaOutside(chromaGamut(flat(0.0f), mask), teal, mask), 0.0);  // nothing to judge by
  EXPECT_EQ(chromaOutside(g, flat(0.0f), mask), 0.0);
  cv::Mat one = none.clone();
  one.at<uint8_t>(60, 80) = 255;
  EXPECT_TRUE(chromaGamut(photo, one).bins.empty());  // one pixel: no bin holds two
  EXPECT_EQ(chromaOutside(g, teal, one), 0.0);        // its own median: at the centre
  EXPECT_THROW(chromaGamut(photo, mask, 0.1f, 0.0), Exception);
  EXPECT_THROW(chromaOutside(g, cv::Mat(kSize, CV_32FC1), mask), Exception);
}

}  // namespace
}  // namespace ps
