#include "photoscene/select/part_selection.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "photoscene/align/align.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/math.hpp"
#include "photoscene/core/rng.hpp"
#include "photoscene/core/color.hpp"

namespace ps {

bool PartSelectionOptions::IsValid(std::string* error) const {
  std::ostringstream os;
  if (k < 1)
    os << "k must be >= 1, got " << k;
  else if (!(footprintPercentile > 0 && footprintPercentile < 1))
    os << "footprintPercentile must be in (0, 1)";
  else if (maxTextureSize < 16)
    os << "maxTextureSize must be >= 16";
  else if (erodePixels < 0)
    os << "erodePixels must be >= 0";
  if (error) *error = os.str();
  return os.str().empty();
}

namespace {

/// Masked Gaussian blur by normalized convolution (0 where no mask pixel is in reach).
cv::Mat maskedBlur(const cv::Mat& values, const cv::Mat& mask01, double sigma) {
  cv::Mat num, den;
  const int r = static_cast<int>(std::ceil(3 * sigma));
  cv::GaussianBlur(values.mul(mask01), num, cv::Size(2 * r + 1, 2 * r + 1), sigma, sigma,
                   cv::BORDER_CONSTANT);
  cv::GaussianBlur(mask01, den, cv::Size(2 * r + 1, 2 * r + 1), sigma, sigma, cv::BORDER_CONSTANT);
  cv::Mat out = num / cv::max(den, 1e-6);
  out.setTo(0, den < 1e-6);
  return out;
}

/// The UV footprint of a pixel (finite differences between masked neighbours) at a percentile.
double footprintAt(const cv::Mat& uv, const cv::Mat& mask, double percentile) {
  std::vector<float> steps;
  for (int y = 0; y + 1 < uv.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    const uint8_t* m1 = mask.ptr<uint8_t>(y + 1);
    const cv::Vec2f* p = uv.ptr<cv::Vec2f>(y);
    const cv::Vec2f* p1 = uv.ptr<cv::Vec2f>(y + 1);
    for (int x = 0; x + 1 < uv.cols; ++x) {
      if (!m[x]) continue;
      if (m[x + 1]) steps.push_back(static_cast<float>(cv::norm(p[x + 1] - p[x])));
      if (m1[x]) steps.push_back(static_cast<float>(cv::norm(p1[x] - p[x])));
    }
  }
  if (steps.empty()) return 0;
  const size_t i = std::min(steps.size() - 1, static_cast<size_t>(percentile * steps.size()));
  std::nth_element(steps.begin(), steps.begin() + i, steps.end());
  return steps[i];
}

/// Labels (CV_32SC1, 1..n, 0 outside) of the mask's pieces in which 4-neighbours are joined when
/// their UVs differ by at most maxStep.
cv::Mat uvPieces(const cv::Mat& uv, const cv::Mat& mask, double maxStep) {
  cv::Mat labels = cv::Mat::zeros(mask.size(), CV_32SC1);
  int next = 0;
  std::vector<cv::Point> stack;
  for (int y0 = 0; y0 < mask.rows; ++y0)
    for (int x0 = 0; x0 < mask.cols; ++x0) {
      if (!mask.at<uint8_t>(y0, x0) || labels.at<int>(y0, x0)) continue;
      labels.at<int>(y0, x0) = ++next;
      stack.assign(1, cv::Point(x0, y0));
      while (!stack.empty()) {
        const cv::Point q = stack.back();
        stack.pop_back();
        const cv::Vec2f a = uv.at<cv::Vec2f>(q);
        const cv::Point nb[4] = {{q.x + 1, q.y}, {q.x - 1, q.y}, {q.x, q.y + 1}, {q.x, q.y - 1}};
        for (const cv::Point& r : nb) {
          if (r.x < 0 || r.y < 0 || r.x >= mask.cols || r.y >= mask.rows) continue;
          if (!mask.at<uint8_t>(r) || labels.at<int>(r)) continue;
          if (cv::norm(uv.at<cv::Vec2f>(r) - a) > maxStep) continue;
          labels.at<int>(r) = next;
          stack.push_back(r);
        }
      }
    }
  return labels;
}

}  // namespace

cv::Mat removeSmoothShading(const cv::Mat& image, const cv::Mat& mask, double sigma) {
  PS_Check(image.type() == CV_32FC3 && mask.type() == CV_8UC1 && image.size() == mask.size(),
           "removeSmoothShading: CV_32FC3 image and CV_8UC1 mask of one size expected");
  cv::Mat out = cv::Mat::zeros(image.size(), CV_32FC3);
  image.copyTo(out, mask);
  if (sigma <= 0) return out;
  cv::Mat m01;
  mask.convertTo(m01, CV_32F, 1.0 / 255.0);
  cv::threshold(m01, m01, 0, 1, cv::THRESH_BINARY);
  cv::Mat lum(image.size(), CV_32FC1);
  double sum = 0, n = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      lum.at<float>(y, x) = luminance(image.at<cv::Vec3f>(y, x));
      if (mask.at<uint8_t>(y, x)) sum += lum.at<float>(y, x), n += 1;
    }
  const double mean = n > 0 ? sum / n : 0;
  if (!(mean > 0)) return out;
  const cv::Mat smooth = maskedBlur(lum, m01, sigma);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      if (!mask.at<uint8_t>(y, x)) continue;
      const float s = std::max(smooth.at<float>(y, x), static_cast<float>(1e-3 * mean));
      out.at<cv::Vec3f>(y, x) *= static_cast<float>(mean / s);
    }
  return out;
}

PartTexture preparePartTexture(const cv::Mat& photo, const cv::Mat& mask, const cv::Mat& uv,
                               const cv::Mat& shading, double shadingSigma,
                               const PartSelectionOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), "invalid PartSelectionOptions: " << why);
  PS_Check(photo.type() == CV_32FC3, "selectForPart: photo must be CV_32FC3");
  PS_Check(mask.type() == CV_8UC1 && mask.size() == photo.size(),
           "selectForPart: mask must be CV_8UC1, photo's size");
  PS_Check(uv.empty() || (uv.type() == CV_32FC2 && uv.size() == photo.size()),
           "selectForPart: uv must be empty or CV_32FC2, photo's size");
  PS_Check(shading.empty() || ((shading.type() == CV_32FC3 || shading.type() == CV_32FC1) &&
                               shading.size() == photo.size()),
           "selectForPart: shading must be empty or CV_32FC1 / CV_32FC3, photo's size");
  const int pixels = cv::countNonZero(mask);
  PS_Check(pixels > 0, "selectForPart: empty mask");

  cv::Mat m = mask != 0;
  if (options.erodePixels > 0) {
    cv::Mat eroded;
    cv::erode(m, eroded,
              cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * options.erodePixels + 1,
                                                                 2 * options.erodePixels + 1)),
              cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, 0);
    if (2 * cv::countNonZero(eroded) >= pixels) m = eroded;
  }
  cv::Mat img = photo;
  if (!shading.empty()) {
    cv::Mat s3;
    if (shading.channels() == 1)
      cv::merge(std::vector<cv::Mat>{shading, shading, shading}, s3);
    else
      s3 = shading;
    img = photo / cv::max(s3, 1e-6);
  }

  PartTexture out;
  if (!uv.empty() && options.unwarp) {
    const double median = footprintAt(uv, m, 0.5),
                 coarse = footprintAt(uv, m, options.footprintPercentile);
    // Shading is smooth within a face but jumps between faces (a sofa's seat and front): remove
    // it per UV-continuous piece (4-neighbours whose UVs differ by more than 4 median footprints
    // belong to different pieces), in the photo frame; pieces under 32 pixels are dropped.
    const cv::Mat pieces = uvPieces(uv, m, 4 * std::max(median, 1e-9));
    double maxLabel = 0;
    cv::minMaxLoc(pieces, nullptr, &maxLabel);
    cv::Mat flat = cv::Mat::zeros(img.size(), CV_32FC3), kept = cv::Mat::zeros(m.size(), CV_8UC1);
    // each piece keeps its own mean level after removeSmoothShading; one material has one
    // albedo on every face, so the levels are brought to the part's pixel-weighted mean (else
    // the faces of a box meet in texture space as steps of light and dark: read as planks)
    struct Level {
      cv::Mat piece;
      cv::Rect box;
      double mean = 0;
      int pixels = 0;
    };
    std::vector<Level> levels;
    for (int label = 1; label <= static_cast<int>(maxLabel); ++label) {
      const cv::Mat piece = pieces == label;
      const int n = cv::countNonZero(piece);
      if (n < 32) continue;
      const cv::Rect box = cv::boundingRect(piece);
      const cv::Mat f = removeSmoothShading(img(box), piece(box), shadingSigma);
      f.copyTo(flat(box), piece(box));
      kept |= piece;
      const cv::Scalar mean = cv::mean(f, piece(box));
      levels.push_back({piece, box, luminance(mean[0], mean[1], mean[2]), n});
    }
    if (levels.size() > 1) {
      double sum = 0, n = 0;
      for (const Level& l : levels) sum += l.mean * l.pixels, n += l.pixels;
      const double target = sum / n;
      for (const Level& l : levels)
        if (l.mean > 1e-12 * target && target > 0) {
          cv::Mat region = flat(l.box);
          const cv::Mat scaled = region * (target / l.mean);
          scaled.copyTo(region, l.piece(l.box));
        }
    }
    if (cv::countNonZero(kept) >= 16) {
      img = flat;
      m = kept;
    }
    align::UnwarpOptions uo;
    uo.texelsPerPixel = coarse > 1e-12 ? std::clamp(median / coarse, 0.25, 1.0) : 1.0;
    uo.maxSize = options.maxTextureSize;
    const align::UnwarpedTexture t = align::unwarpToTexture(img, uv, m, uo);
    // close one-texel holes and fill them from their neighbours
    cv::Mat closed;
    cv::morphologyEx(t.coverage, closed, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    cv::Mat filled = t.texture.clone();
    cv::Mat holes = closed & ~t.coverage;
    if (cv::countNonZero(holes) > 0) {
      cv::Mat c01;
      t.coverage.convertTo(c01, CV_32F, 1.0 / 255.0);
      std::vector<cv::Mat> ch;
      cv::split(t.texture, ch);
      for (cv::Mat& c : ch) c = maskedBlur(c, c01, 1.0);
      cv::Mat blurred;
      cv::merge(ch, blurred);
      blurred.copyTo(filled, holes);
    }
    out.image = filled;
    out.mask = closed;
    out.unwarped = true;
    if (cv::countNonZero(out.mask) >= 16) {
      out.image.setTo(cv::Scalar(0, 0, 0), out.mask == 0);
      return out;
    }
  }
  const cv::Rect box = cv::boundingRect(m);
  out.image = img(box).clone();
  out.mask = m(box).clone();
  out.unwarped = false;
  out.image = removeSmoothShading(out.image, out.mask, shadingSigma);
  return out;
}

GraphChoice selectForPart(const ExemplarBank& bank, const cv::Mat& photo, const cv::Mat& mask,
                          const cv::Mat& uv, const cv::Mat& shading,
                          const PartSelectionOptions& options) {
  const PartTexture t =
      preparePartTexture(photo, mask, uv, shading, bank.options().shadingSigma, options);
  const std::vector<float> key = describeTexture(t.image, t.mask, bank.options());
  if (!options.category.empty()) return bank.selectInCategory(key, options.k, options.category);
  return bank.select(key, options.k, options.categoryFirst, options.distinctDraws);
}

// ---------------------------------------------------------------- observation model

namespace {

std::vector<cv::Mat> mipChain(const cv::Mat& map) {
  std::vector<cv::Mat> chain{map};
  while (chain.back().cols > 2) {
    cv::Mat half;
    cv::resize(chain.back(), half, cv::Size(chain.back().cols / 2, chain.back().rows / 2), 0, 0,
               cv::INTER_AREA);
    chain.push_back(half);
  }
  return chain;
}

}  // namespace

ObservedPlane renderObservedPlane(const MaterialMaps& maps, const ObservedPlaneParams& p) {
  PS_Check(!maps.albedo.empty() && !maps.normal.empty(),
           "renderObservedPlane needs albedo and normal maps");
  PS_Check(p.width >= 8 && p.height >= 8, "renderObservedPlane: image too small");
  const std::vector<cv::Mat> albedo = mipChain(maps.albedo), normal = mipChain(maps.normal);
  const int W = p.width, H = p.height, ss = 2;
  const double f = 0.5 * W / std::tan(radians(30.0));  // 60-degree horizontal field of view
  const double cx = 0.5 * W, cy = 0.5 * H, D = 1.0;
  // plane through (0, 0, D), normal tilted away from -z by tilt, in the direction yaw
  const double tilt = radians(static_cast<double>(p.tiltDeg)),
               yaw = radians(static_cast<double>(p.yawDeg));
  const Vec3d a(std::cos(yaw), std::sin(yaw), 0);  // tilt axis direction in the image
  const Vec3d b(-std::sin(yaw), std::cos(yaw), 0);
  const Vec3d n =
      (-std::cos(tilt) * Vec3d(0, 0, 1) + std::sin(tilt) * b).normalized();  // faces the camera
  const Vec3d e1 = a;                                                        // in the plane
  const Vec3d e2 = n.cross(e1).normalized();                                 // in the plane
  const Vec3d P0(0, 0, D);
  const double extent = D * W / f;  // plane width seen at the center
  const float th = radians(p.rotationDeg), c = std::cos(th), s = std::sin(th);
  const int texels = maps.albedo.cols;
  const Vec3f light = Vec3f(-0.45f, 0.55f, 0.70f).normalized();

  ObservedPlane out;
  out.image = cv::Mat::zeros(H, W, CV_32FC3);
  out.uv = cv::Mat::zeros(H, W, CV_32FC2);
  out.mask = cv::Mat::zeros(H, W, CV_8UC1);
  auto uvAt = [&](double x, double y, bool* ok) {
    const Vec3d d((x - cx) / f, -(y - cy) / f, 1.0);  // y up in camera space
    const double dn = n.dot(d);
    *ok = dn < -std::cos(radians(80.0)) * d.norm();
    const double t = n.dot(P0) / (dn == 0 ? 1e-12 : dn);
    const Vec3d q = t * d - P0;
    return cv::Vec2d(q.dot(e1) / extent, q.dot(e2) / extent);
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      bool ok = false, okx = false, oky = false;
      const cv::Vec2d uv = uvAt(x, y, &ok), ux = uvAt(x + 1, y, &okx), uy = uvAt(x, y + 1, &oky);
      if (!ok) continue;
      // footprint in texels of the finest map: picks the mip level (half a pixel: 2 x 2 samples)
      const double foot = 0.5 * p.repeats * texels * std::max(cv::norm(ux - uv), cv::norm(uy - uv));
      const int level = std::clamp(static_cast<int>(std::floor(std::log2(std::max(1.0, foot)))), 0,
                                   static_cast<int>(albedo.size()) - 1);
      cv::Vec3f acc(0, 0, 0);
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          bool okS = false;
          const cv::Vec2d q = uvAt(x - 0.5 + (sx + 0.5) / ss, y - 0.5 + (sy + 0.5) / ss, &okS);
          const float su = static_cast<float>(p.repeats * q[0]),
                      sv = static_cast<float>(p.repeats * q[1]);
          const float tu = c * su - s * sv, tv = s * su + c * sv;
          const cv::Vec3f al = samplePeriodic(albedo[level], tu, tv);
          const cv::Vec3f nt = samplePeriodic(normal[level], tu, tv);
          // tangent frame on the plane: shading in the plane's frame (light fixed relative to it)
          const Vec3f T(c, -s, 0), B(s, c, 0), N(0, 0, 1);
          Vec3f nn = nt[0] * T + nt[1] * B + nt[2] * N;
          const float len = nn.norm();
          nn = len > 1e-6f ? Vec3f(nn / len) : N;
          const float shade = 0.35f + 0.65f * std::max(0.0f, nn.dot(light));
          acc += al * shade;
        }
      acc *= 1.0f / (ss * ss);
      out.image.at<cv::Vec3f>(y, x) =
          cv::Vec3f(acc[0] * p.lightColor[0], acc[1] * p.lightColor[1], acc[2] * p.lightColor[2]);
      out.uv.at<cv::Vec2f>(y, x) = cv::Vec2f(static_cast<float>(uv[0]), static_cast<float>(uv[1]));
      out.mask.at<uint8_t>(y, x) = 255;
    }
  Rng rng(p.seed, 29);
  // a smooth shading gradient along a random direction, plus a soft hot spot
  const float gdir = rng.uniform(0.f, 2 * static_cast<float>(kPi));
  const float hx = rng.uniform(0.f, 1.f) * W, hy = rng.uniform(0.f, 1.f) * H,
              hs = rng.uniform(0.3f, 0.8f) * W;
  const float hot = rng.uniform(0.f, 0.5f) * p.gradient;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const float r = ((x - cx) * std::cos(gdir) + (y - cy) * std::sin(gdir)) / W;
      const float d2 = ((x - hx) * (x - hx) + (y - hy) * (y - hy)) / (hs * hs);
      out.image.at<cv::Vec3f>(y, x) *= std::exp(p.gradient * r + hot * std::exp(-d2));
    }
  if (p.blurSigma > 0.05f) cv::GaussianBlur(out.image, out.image, cv::Size(0, 0), p.blurSigma);
  if (p.noise > 0)
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        cv::Vec3f& v = out.image.at<cv::Vec3f>(y, x);
        for (int k = 0; k < 3; ++k) v[k] = std::max(0.0f, v[k] * (1 + p.noise * rng.normal()));
      }
  if (p.oddMask) {
    // a random ellipse with a random notch cut out: an odd, non-convex part outline
    cv::Mat shape = cv::Mat::zeros(H, W, CV_8UC1);
    const cv::Point center(static_cast<int>(rng.uniform(0.35f, 0.65f) * W),
                           static_cast<int>(rng.uniform(0.35f, 0.65f) * H));
    const cv::Size axes(static_cast<int>(rng.uniform(0.3f, 0.6f) * W),
                        static_cast<int>(rng.uniform(0.3f, 0.6f) * H));
    cv::ellipse(shape, center, axes, rng.uniform(0.f, 180.f), 0, 360, cv::Scalar(255), cv::FILLED);
    const cv::Point n0(static_cast<int>(rng.uniform(0.f, 1.f) * W),
                       static_cast<int>(rng.uniform(0.f, 1.f) * H));
    cv::rectangle(shape,
                  cv::Rect(n0, cv::Size(static_cast<int>(0.25f * W), static_cast<int>(0.25f * H))),
                  cv::Scalar(0), cv::FILLED);
    out.mask &= shape;
  }
  out.uv.setTo(cv::Scalar(0, 0), out.mask == 0);
  out.image.setTo(cv::Scalar(0, 0, 0), out.mask == 0);
  return out;
}

ObservedPlaneParams randomObservation(const ObservationRanges& r, Rng& rng) {
  ObservedPlaneParams p;
  p.width = r.width;
  p.height = r.height;
  p.tiltDeg = rng.uniform(0.f, r.maxTiltDeg);
  p.yawDeg = rng.uniform(0.f, 360.f);
  p.repeats = std::exp(rng.uniform(std::log(r.minRepeats), std::log(r.maxRepeats)));
  p.rotationDeg = rng.uniform(0.f, 360.f);
  p.gradient = rng.uniform(-r.maxGradient, r.maxGradient);
  p.blurSigma = rng.uniform(0.f, r.maxBlurSigma);
  p.noise = rng.uniform(0.f, r.maxNoise);
  p.oddMask = rng.uniform() < r.oddMaskProbability;
  p.seed = rng.nextU64();
  return p;
}

}  // namespace ps
