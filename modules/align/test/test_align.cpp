#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "photoscene/align.hpp"
#include "photoscene/core.hpp"

namespace ps::align {
namespace {

/// A render-frame part-id image with three parts: a floor band, a box, a disc.
cv::Mat syntheticPartIds(cv::Size size) {
  cv::Mat ids(size, CV_32SC1, cv::Scalar(-1));
  ids(cv::Rect(0, size.height * 2 / 3, size.width, size.height / 3)).setTo(0);
  ids(cv::Rect(20, 20, 60, 40)).setTo(1);
  cv::circle(ids, cv::Point(150, 50), 25, cv::Scalar(2), cv::FILLED);
  return ids;
}

TEST(Align_Masks, part_masks_from_part_ids) {
  const cv::Mat ids = syntheticPartIds(cv::Size(200, 150));
  const auto masks = partMasks(ids);
  ASSERT_EQ(masks.size(), 3u);
  EXPECT_EQ(cv::countNonZero(masks.at(1)), 60 * 40);
  EXPECT_EQ(partMasks(ids, 3000).size(), 1u);  // only the floor band is that large
}

TEST(Align_Match, shifted_dilated_regions_match_their_parts_and_noise_stays_unmatched) {
  const cv::Size size(200, 150);
  const auto geo = partMasks(syntheticPartIds(size));
  // photo labels: each part's mask shifted and dilated (coarse CAD vs photo), plus noise regions
  cv::Mat labels = cv::Mat::zeros(size, CV_32SC1);
  const std::map<int, cv::Point> shift = {{0, {0, 4}}, {1, {5, -3}}, {2, {-4, 2}}};
  for (const auto& [part, m] : geo) {
    cv::Mat moved, dil;
    const cv::Mat T = (cv::Mat_<double>(2, 3) << 1, 0, shift.at(part).x, 0, 1, shift.at(part).y);
    cv::warpAffine(m, moved, T, size, cv::INTER_NEAREST);
    cv::dilate(moved, dil, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
    labels.setTo(10 + part, dil);
  }
  Rng rng(1);
  for (int k = 0; k < 6; ++k) {  // small noise blobs
    cv::circle(labels, cv::Point(rng.uniform(0, 200), rng.uniform(0, 90)), 3, cv::Scalar(50 + k), cv::FILLED);
  }
  const MatchResult r = matchRegions(labels, geo, {});
  for (const auto& [part, m] : geo) {
    ASSERT_TRUE(r.photoMasks.count(part)) << part;
    EXPECT_GT(iou(r.photoMasks.at(part), (labels == 10 + part)), 0.99);
  }
  for (const auto& reg : r.regions) {
    if (reg.label >= 50) {
      EXPECT_EQ(reg.part, -1) << "noise region " << reg.label << " iou " << reg.iou;
      EXPECT_LT(reg.iou, 0.1);
    } else {
      EXPECT_EQ(reg.part, reg.label - 10);
      EXPECT_GT(reg.iou, 0.5);
    }
  }
  EXPECT_GE(r.unmatched().size(), 5u);  // blobs may merge into one label only if overlapping
  // a threshold above a region's IoU leaves it unmatched; pinning overrides the threshold
  MatchOptions strict;
  strict.minIou = 0.999;
  const MatchResult s = matchRegions(labels, geo, {{11, 1}}, strict);
  for (const auto& reg : s.regions) {
    if (reg.label == 11) EXPECT_EQ(reg.part, 1);
    else EXPECT_EQ(reg.part, -1);
  }
}

TEST(Align_Warp, bounding_box_affine_maps_corners_exactly) {
  Rng rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    cv::Mat geo = cv::Mat::zeros(120, 160, CV_8UC1), photo = cv::Mat::zeros(100, 140, CV_8UC1);
    const cv::Rect g(rng.uniformInt(60), rng.uniformInt(50), 10 + rng.uniformInt(90), 5 + rng.uniformInt(60));
    const cv::Rect p(rng.uniformInt(50), rng.uniformInt(40), 3 + rng.uniformInt(80), 4 + rng.uniformInt(50));
    cv::ellipse(geo, cv::RotatedRect(cv::Point2f(g.x + g.width / 2.f, g.y + g.height / 2.f), cv::Size2f(g.width, g.height), 0),
                cv::Scalar(255), cv::FILLED);
    photo(p).setTo(255);
    const cv::Rect2d bg = maskBox(geo), bp = maskBox(photo);
    const cv::Matx23d A = boxAffine(geo, photo);
    auto map = [&](double x, double y) { return cv::Point2d(A(0, 0) * x + A(0, 2), A(1, 1) * y + A(1, 2)); };
    const cv::Point2d tl = map(bp.x, bp.y), br = map(bp.x + bp.width, bp.y + bp.height);
    EXPECT_NEAR(tl.x, bg.x, 0.5);
    EXPECT_NEAR(tl.y, bg.y, 0.5);
    EXPECT_NEAR(br.x, bg.x + bg.width, 0.5);
    EXPECT_NEAR(br.y, bg.y + bg.height, 0.5);
    // pixel-center corners too
    const cv::Point2d c0 = map(p.x, p.y);
    EXPECT_NEAR(c0.x, bg.x + 0.5 * bg.width / bp.width, 1e-9);
  }
}

TEST(Align_Warp, aligned_buffers_come_from_inside_the_part) {
  const cv::Size size(200, 150);
  const cv::Mat ids = syntheticPartIds(size);
  const auto geo = partMasks(ids);
  // a UV buffer that is 7 inside the box part and 0 elsewhere
  cv::Mat uv(size, CV_32FC2, cv::Scalar(0, 0));
  uv.setTo(cv::Scalar(7, 7), geo.at(1));
  cv::Mat photo = cv::Mat::zeros(size, CV_8UC1);
  photo(cv::Rect(30, 25, 75, 45)).setTo(255);  // the photo shows the box larger and shifted
  const AlignedPart a = alignPart(1, geo.at(1), photo, {uv, ids});
  EXPECT_EQ(a.photoPixels, 75 * 45);
  EXPECT_GT(cv::countNonZero(a.mask), 0.95 * a.photoPixels);
  EXPECT_EQ(a.droppedPixels, a.photoPixels - cv::countNonZero(a.mask));
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      if (!a.mask.at<uint8_t>(y, x)) continue;
      EXPECT_FLOAT_EQ(a.buffers[0].at<cv::Vec2f>(y, x)[0], 7.0f);
      EXPECT_EQ(a.buffers[1].at<int>(y, x), 1);
    }
  // a part with an empty photo mask aligns to nothing without failing
  const AlignedPart none = alignPart(2, geo.at(2), cv::Mat::zeros(size, CV_8UC1), {uv});
  EXPECT_EQ(cv::countNonZero(none.mask), 0);
}

/// A textured plane seen in perspective: UV from a homography, photo = texture at UV.
struct PlaneView {
  cv::Mat uv, photo, mask;
};

cv::Vec3f smoothTexture(double u, double v) {
  return cv::Vec3f(0.5f + 0.3f * std::sin(2 * kPiD * u * 1.3), 0.4f + 0.25f * std::cos(2 * kPiD * v * 0.9),
                   0.3f + 0.2f * std::sin(2 * kPiD * (u + v) * 0.7));
}

PlaneView makePlane() {
  PlaneView p;
  const cv::Size size(240, 180);
  p.uv.create(size, CV_32FC2);
  p.photo.create(size, CV_32FC3);
  p.mask = cv::Mat::zeros(size, CV_8UC1);
  // UV = H * (x, y, 1), a mild perspective
  const cv::Matx33d H(0.012, 0.002, -0.3, 0.0005, -0.011, 1.8, 0.0, 0.0006, 1.0);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const cv::Vec3d q = H * cv::Vec3d(x, y, 1);
      const double u = q[0] / q[2], v = q[1] / q[2];
      p.uv.at<cv::Vec2f>(y, x) = cv::Vec2f(static_cast<float>(u), static_cast<float>(v));
      p.photo.at<cv::Vec3f>(y, x) = smoothTexture(u, v);
      const bool inside = (x - 120) * (x - 120) / (100.0 * 100) + (y - 90) * (y - 90) / (70.0 * 70) < 1;
      p.mask.at<uint8_t>(y, x) = inside ? 255 : 0;
    }
  return p;
}

TEST(Align_Unwarp, unwarp_then_rerender_reproduces_the_texture_where_covered) {
  const PlaneView p = makePlane();
  const UnwarpedTexture t = unwarpToTexture(p.photo, p.uv, p.mask);
  ASSERT_GT(t.texelsPerUv, 0);
  EXPECT_GT(cv::countNonZero(t.coverage), 0.3 * t.coverage.total());
  // texture against the analytic texture at covered texels
  double err = 0, ref = 0;
  for (int y = 0; y < t.texture.rows; ++y)
    for (int x = 0; x < t.texture.cols; ++x) {
      if (!t.coverage.at<uint8_t>(y, x)) continue;
      const double u = t.uvMin[0] + x / t.texelsPerUv, v = t.uvMax[1] - y / t.texelsPerUv;
      err += cv::norm(t.texture.at<cv::Vec3f>(y, x) - smoothTexture(u, v), cv::NORM_L1);
      ref += cv::norm(smoothTexture(u, v), cv::NORM_L1);
    }
  EXPECT_LT(err / ref, 0.02);
  // re-rendering through the same UVs gives the photo back
  const cv::Mat back = sampleTexture(t, p.uv, p.mask);
  cv::Mat diff;
  cv::absdiff(back, p.photo, diff);
  const double rel = cv::sum(diff.mul(cv::Mat(diff.size(), CV_32FC3, cv::Scalar(1, 1, 1)), 1.0)).dot(cv::Scalar(1, 1, 1, 0));
  double photoSum = 0;
  for (int y = 0; y < p.photo.rows; ++y)
    for (int x = 0; x < p.photo.cols; ++x)
      if (p.mask.at<uint8_t>(y, x)) photoSum += cv::norm(p.photo.at<cv::Vec3f>(y, x), cv::NORM_L1);
  cv::Mat maskedDiff;
  diff.copyTo(maskedDiff, p.mask);
  const cv::Scalar s = cv::sum(maskedDiff);
  EXPECT_LT((s[0] + s[1] + s[2]) / photoSum, 0.02) << rel;
}

TEST(Align_Unwarp, degenerate_inputs_do_not_produce_nan) {
  const PlaneView p = makePlane();
  cv::Mat one = cv::Mat::zeros(p.mask.size(), CV_8UC1);
  one.at<uint8_t>(90, 120) = 255;
  const UnwarpedTexture t1 = unwarpToTexture(p.photo, p.uv, one);
  EXPECT_TRUE(allFinite(t1.texture));
  EXPECT_EQ(cv::countNonZero(t1.coverage), 1);
  const UnwarpedTexture t0 = unwarpToTexture(p.photo, p.uv, cv::Mat::zeros(p.mask.size(), CV_8UC1));
  EXPECT_EQ(cv::countNonZero(t0.coverage), 0);
  cv::Mat flat(p.uv.size(), CV_32FC2, cv::Scalar(0.3, 0.3));  // all pixels at one UV
  const UnwarpedTexture tf = unwarpToTexture(p.photo, flat, p.mask);
  EXPECT_TRUE(allFinite(tf.texture));
}

TEST(Align_Proposals, superpixels_snap_the_geometry_mask_to_photo_edges) {
  // photo: a bright rectangle on a dark textured background; geometry mask: the same rectangle
  // shifted by 6 px (coarse CAD)
  const cv::Size size(160, 120);
  Rng rng(9);
  cv::Mat photo(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const float n = 0.02f * rng.uniform();
      photo.at<cv::Vec3f>(y, x) = cv::Vec3f(0.05f + n, 0.06f + n, 0.08f + n);
    }
  const cv::Rect truth(40, 30, 70, 50);
  photo(truth).setTo(cv::Scalar(0.7, 0.5, 0.3));
  cv::Mat geo = cv::Mat::zeros(size, CV_8UC1);
  geo(truth + cv::Point(6, 4)).setTo(255);
  cv::Mat truthMask = cv::Mat::zeros(size, CV_8UC1);
  truthMask(truth).setTo(255);
  std::map<int, int> pinned;
  const cv::Mat labels = proposeRegions(photo, {{3, geo}}, &pinned);
  const MatchResult r = matchRegions(labels, {{3, geo}}, pinned);
  ASSERT_TRUE(r.photoMasks.count(3));
  EXPECT_GT(iou(r.photoMasks.at(3), truthMask), iou(geo, truthMask));
  EXPECT_GT(iou(r.photoMasks.at(3), truthMask), 0.85);
}

TEST(Align_ViewChoice, prefers_large_frontal_agreeing_views) {
  std::vector<PartObservation> obs = {
      {0, 5000, 0.9, cv::Vec3f(0.3f, 0.3f, 0.3f)},
      {1, 9000, 0.3, cv::Vec3f(0.31f, 0.3f, 0.29f)},  // larger but grazing: 2700 < 4500
      {2, 8000, 0.9, cv::Vec3f(0.9f, 0.9f, 0.9f)},    // largest score but a highlight
      {3, 4000, 0.95, cv::Vec3f(0.3f, 0.29f, 0.3f)},
  };
  const ViewChoice c = chooseView(obs);
  EXPECT_EQ(c.view, 0) << c.reason;
  ASSERT_EQ(c.scores.size(), 4u);
  EXPECT_LT(c.scores[2], c.scores[0]);
  EXPECT_EQ(chooseView({}).view, -1);
  const cv::Mat img(4, 4, CV_32FC3, cv::Scalar(0.2, 0.4, 0.6));
  const cv::Vec3f med = maskedMedian(img, cv::Mat(4, 4, CV_8UC1, cv::Scalar(255)));
  EXPECT_FLOAT_EQ(med[1], 0.4f);
}

TEST(Align_ViewChoice, two_views_prefer_the_darker_one_where_they_disagree_after_exposure) {
  // view 1's photo is twice as bright overall (exposure 2): its median agrees after the division
  std::vector<PartObservation> obs = {
      {0, 5000, 0.9, cv::Vec3f(0.3f, 0.3f, 0.3f)},
      {1, 6000, 0.9, cv::Vec3f(0.6f, 0.62f, 0.58f)},
  };
  ViewChoice c = chooseView(obs, {1.0, 2.0});
  EXPECT_EQ(c.view, 1) << c.reason;  // larger, and agreeing once the exposure is taken out
  ASSERT_EQ(c.agreement.size(), 2u);
  EXPECT_GT(c.agreement[1], 0.9);
  // without the exposure the brighter view looks like a highlight: the darker one wins
  c = chooseView(obs);
  EXPECT_EQ(c.view, 0) << c.reason;
  EXPECT_LT(c.agreement[1], 0.1);
  EXPECT_DOUBLE_EQ(c.agreement[0], 1.0);
}

TEST(Align_ViewChoice, exposures_from_the_parts_two_views_share) {
  // four parts; view 1 at exposure 0.5, view 2 at 1.6; one part has a highlight in view 2
  const double e[3] = {1.0, 0.5, 1.6};
  const float albedo[4] = {0.2f, 0.5f, 0.35f, 0.7f};
  std::vector<std::vector<PartObservation>> parts(4);
  for (int p = 0; p < 4; ++p)
    for (int v = 0; v < 3; ++v) {
      float x = static_cast<float>(albedo[p] * e[v]);
      if (p == 3 && v == 2) x *= 1.8f;  // the highlight
      parts[p].push_back({v, 1000, 0.8, cv::Vec3f(x, x, x)});
    }
  parts.push_back({{0, 10, 0.8, cv::Vec3f(0.9f, 0.9f, 0.9f)},  // too small to count
                   {1, 10, 0.8, cv::Vec3f(0.01f, 0.01f, 0.01f)}});
  const std::vector<double> got = estimateExposures(parts, 3);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_DOUBLE_EQ(got[0], 1.0);
  EXPECT_NEAR(got[1], 0.5, 0.01);
  EXPECT_NEAR(got[2], 1.6, 0.05);
  EXPECT_EQ(estimateExposures(parts, 1), std::vector<double>{1.0});
  // a view no part is seen in keeps 1
  EXPECT_DOUBLE_EQ(estimateExposures(parts, 4)[3], 1.0);
  // one photo twice as bright: its exposure doubles, the others do not move
  for (auto& obs : parts)
    for (PartObservation& o : obs)
      if (o.view == 1) o.medianColor *= 2.0f;
  const std::vector<double> twice = estimateExposures(parts, 3);
  EXPECT_NEAR(twice[1] / got[1], 2.0, 1e-4);
  EXPECT_NEAR(twice[2] / got[2], 1.0, 1e-4);
}

// ---------------------------------------------------------------- masks across views

/// A pinhole camera at `eye` looking down -z (image x along +x, y along -y), focal 50 px, 64 x 48.
struct TopCamera {
  Vec3d eye;
  static constexpr int kWidth = 64, kHeight = 48;
  static constexpr double kFocal = 50, kCx = 31.5, kCy = 23.5;
  bool project(const Vec3d& p, Vec2d* pixel) const {
    const double depth = eye.z() - p.z();
    if (depth <= 0) return false;
    *pixel =
        Vec2d(kCx + kFocal * (p.x() - eye.x()) / depth, kCy - kFocal * (p.y() - eye.y()) / depth);
    return true;
  }
  /// The G-buffer of the plane z = 0 with part 1 on the square |x|, |y| <= 0.4 and part 0 around.
  void gbuffer(cv::Mat* position, cv::Mat* partId) const {
    *position = cv::Mat(kHeight, kWidth, CV_32FC3);
    *partId = cv::Mat(kHeight, kWidth, CV_32SC1);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const Vec3d p(eye.x() + (x - kCx) / kFocal * eye.z(),
                      eye.y() - (y - kCy) / kFocal * eye.z(), 0);
        position->at<cv::Vec3f>(y, x) = cv::Vec3f(float(p.x()), float(p.y()), 0.0f);
        partId->at<int>(y, x) = std::abs(p.x()) <= 0.4 && std::abs(p.y()) <= 0.4 ? 1 : 0;
      }
  }
};

cv::Mat partMask(const cv::Mat& partId, int part) {
  cv::Mat m = partId == part;
  cv::erode(m, m, cv::Mat());  // the interior, as M_aln keeps it
  return m;
}

TEST(Align_MaskConsistency, masks_of_the_same_surface_agree_and_a_shifted_one_does_not) {
  const TopCamera a{Vec3d(0, 0, 2)}, b{Vec3d(0.3, -0.1, 1.8)};
  cv::Mat posA, idsA, posB, idsB;
  a.gbuffer(&posA, &idsA);
  b.gbuffer(&posB, &idsB);
  const cv::Mat maskA = partMask(idsA, 1), maskB = partMask(idsB, 1);
  const Projector projectB = [&](const Vec3d& p, Vec2d* q) { return b.project(p, q); };
  const MaskConsistency same = maskConsistency(1, maskA, posA, maskB, posB, idsB, projectB);
  EXPECT_EQ(same.pixels, cv::countNonZero(maskA));
  EXPECT_GT(same.seen, same.pixels / 2) << "B sees most of the square";
  EXPECT_GE(same.share(), 0.97);
  // the region matched to the part in B sits 8 pixels to the right of where the part is
  cv::Mat shifted = cv::Mat::zeros(maskB.size(), CV_8UC1);
  maskB(cv::Rect(0, 0, maskB.cols - 8, maskB.rows))
      .copyTo(shifted(cv::Rect(8, 0, maskB.cols - 8, maskB.rows)));
  const MaskConsistency off = maskConsistency(1, maskA, posA, shifted, posB, idsB, projectB);
  EXPECT_EQ(off.seen, same.seen);
  EXPECT_LT(off.share(), 0.8);
  // a point another surface hides from B is not seen: a box-top (part 1 raised to z = 0.5 in B's
  // G-buffer) over the square hides A's points, which B's positions no longer hold
  cv::Mat raised = posB.clone();
  for (int y = 0; y < raised.rows; ++y)
    for (int x = 0; x < raised.cols; ++x)
      if (idsB.at<int>(y, x) == 1) raised.at<cv::Vec3f>(y, x)[2] = 0.5f;
  EXPECT_EQ(maskConsistency(1, maskA, posA, maskB, raised, idsB, projectB).seen, 0);
  // no pixel of A's mask: nothing seen, the share is -1
  const MaskConsistency none =
      maskConsistency(1, cv::Mat::zeros(maskA.size(), CV_8UC1), posA, maskB, posB, idsB, projectB);
  EXPECT_EQ(none.seen, 0);
  EXPECT_DOUBLE_EQ(none.share(), -1.0);
}

}  // namespace
}  // namespace ps::align
