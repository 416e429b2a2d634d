#include "photoscene/align/view_alignment.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace ps::align {

ViewAlignment alignView(const cv::Mat& photo, const cv::Mat& labels,
                        const std::map<int, int>& pinned, const cv::Mat& partId,
                        const std::vector<cv::Mat>& coverage) {
  ViewAlignment out;
  // M_geo: the interior of each part (coverage ~1: no pixel mixes two parts)
  const std::map<int, cv::Mat> geo = partMasks(partId);
  std::map<int, int> pins = pinned;
  cv::Mat regions = labels;
  if (regions.empty()) regions = proposeRegions(photo, geo, &pins);
  MatchResult match = matchRegions(regions, geo, pins);
  out.lightMask = cv::Mat::zeros(photo.size(), CV_8UC1);
  for (const auto& [part, photoMask] : match.photoMasks) {
    out.photoMask[part] = photoMask;
    if (!geo.count(part) || cv::countNonZero(photoMask) == 0) {
      out.warp[part] = cv::Matx23d(1, 0, 0, 0, 1, 0);
      out.fitMask[part] = cv::Mat::zeros(photoMask.size(), CV_8UC1);
      continue;
    }
    const cv::Mat& geoMask = geo.at(part);
    const cv::Matx23d A = boxAffine(geoMask, photoMask);
    cv::Mat warpedPhotoMask;
    cv::warpAffine(photoMask, warpedPhotoMask, cv::Mat(A), geoMask.size(), cv::INTER_NEAREST,
                   cv::BORDER_CONSTANT, 0);
    cv::Mat interior;
    cv::threshold(coverage[part], interior, 0.99, 255, cv::THRESH_BINARY);
    interior.convertTo(interior, CV_8UC1);
    cv::Mat fit = geoMask & warpedPhotoMask & interior;
    if (cv::countNonZero(fit) == 0) fit = geoMask & warpedPhotoMask;  // thin parts: no interior
    out.warp[part] = A;
    out.fitMask[part] = fit;
    out.lightMask |= geoMask & photoMask & interior;
  }
  out.regions = std::move(match.regions);
  return out;
}

std::optional<PartObservation> observePart(const cv::Mat& partPhoto, const cv::Mat& fitMask,
                                           const cv::Mat& normalShading, const cv::Mat& position,
                                           const Vec3d& cam) {
  const int pixels = cv::countNonZero(fitMask);
  if (pixels == 0) return std::nullopt;
  PartObservation o;
  o.pixels = pixels;
  double cosSum = 0;
  for (int y = 0; y < fitMask.rows; ++y)
    for (int x = 0; x < fitMask.cols; ++x) {
      if (!fitMask.at<uint8_t>(y, x)) continue;
      const cv::Vec3f n = normalShading.at<cv::Vec3f>(y, x);
      const cv::Vec3f pos = position.at<cv::Vec3f>(y, x);
      Vec3d d(cam.x() - pos[0], cam.y() - pos[1], cam.z() - pos[2]);
      d.normalize();
      cosSum += std::abs(n[0] * d.x() + n[1] * d.y() + n[2] * d.z());
    }
  o.meanCosine = cosSum / pixels;
  o.medianColor = maskedMedian(partPhoto, fitMask);
  return o;
}

MaskConsistency maskConsistency(int part, const cv::Mat& maskA, const cv::Mat& positionA,
                                const cv::Mat& maskB, const cv::Mat& positionB,
                                const cv::Mat& partIdB, const Projector& projectB) {
  MaskConsistency c;
  const auto at = [](const cv::Mat& position, int x, int y) {
    const cv::Vec3f p = position.at<cv::Vec3f>(y, x);
    return Vec3d(p[0], p[1], p[2]);
  };
  constexpr int kNeighbour[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (int y = 0; y < maskA.rows; ++y)
    for (int x = 0; x < maskA.cols; ++x) {
      if (!maskA.at<uint8_t>(y, x)) continue;
      ++c.pixels;
      const Vec3d point = at(positionA, x, y);
      Vec2d q;
      if (!projectB(point, &q)) continue;
      const int bx = static_cast<int>(std::lround(q.x())),
                by = static_cast<int>(std::lround(q.y()));
      // the nearest pixel and its four neighbours inside B's image and on the part
      if (bx < 1 || by < 1 || bx >= partIdB.cols - 1 || by >= partIdB.rows - 1) continue;
      if (partIdB.at<int>(by, bx) != part) continue;
      const Vec3d surface = at(positionB, bx, by);
      double spacing = 0;
      bool interior = true;
      for (const auto& d : kNeighbour) {
        interior = interior && partIdB.at<int>(by + d[1], bx + d[0]) == part;
        spacing = std::max(spacing, (at(positionB, bx + d[0], by + d[1]) - surface).norm());
      }
      if (!interior || (point - surface).norm() > 1.5 * spacing) continue;
      ++c.seen;
      c.inside += maskB.at<uint8_t>(by, bx) != 0;
    }
  return c;
}

}  // namespace ps::align
