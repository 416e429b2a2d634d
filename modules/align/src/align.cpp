#include "photoscene/align/align.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>
#include <set>

#include "photoscene/core/color.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"

namespace ps::align {

bool MatchOptions::IsValid(std::string* error) const {
  if (!(minIou >= 0 && minIou <= 1)) {
    if (error) *error = "minIou must be in [0, 1]";
    return false;
  }
  return true;
}

bool ProposalOptions::IsValid(std::string* error) const {
  if (superpixelSize < 2 || !(ruler > 0) || !(minCoverage > 0 && minCoverage <= 1)) {
    if (error) *error = "superpixelSize >= 2, ruler > 0, minCoverage in (0, 1]";
    return false;
  }
  return true;
}

bool UnwarpOptions::IsValid(std::string* error) const {
  if (!(texelsPerPixel > 0) || maxSize < 2) {
    if (error) *error = "texelsPerPixel > 0 and maxSize >= 2";
    return false;
  }
  return true;
}

std::map<int, cv::Mat> partMasks(const cv::Mat& partIds, int minPixels) {
  checkImage(partIds, CV_32SC1, "partIds");
  std::map<int, int> counts;
  for (int y = 0; y < partIds.rows; ++y) {
    const int* p = partIds.ptr<int>(y);
    for (int x = 0; x < partIds.cols; ++x)
      if (p[x] >= 0) counts[p[x]]++;
  }
  std::map<int, cv::Mat> masks;
  for (const auto& [part, n] : counts)
    if (n >= minPixels) masks[part] = (partIds == part);
  return masks;
}

double iou(const cv::Mat& a, const cv::Mat& b) {
  checkImage(a, CV_8UC1, "iou mask a");
  checkImage(b, CV_8UC1, a.size(), "iou mask b");
  int inter = 0, uni = 0;
  for (int y = 0; y < a.rows; ++y) {
    const uint8_t* pa = a.ptr<uint8_t>(y);
    const uint8_t* pb = b.ptr<uint8_t>(y);
    for (int x = 0; x < a.cols; ++x) {
      inter += (pa[x] && pb[x]);
      uni += (pa[x] || pb[x]);
    }
  }
  return uni ? static_cast<double>(inter) / uni : 0.0;
}

std::vector<int> MatchResult::unmatched() const {
  std::vector<int> out;
  for (const auto& r : regions)
    if (r.part < 0) out.push_back(r.label);
  return out;
}

MatchResult matchRegions(const cv::Mat& labels, const std::map<int, cv::Mat>& geoMasks,
                         const std::map<int, int>& pinned, const MatchOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
  checkImage(labels, CV_32SC1, "labels");
  std::vector<int> parts;
  std::vector<const cv::Mat*> masks;
  std::map<int, int> area;
  for (const auto& [part, m] : geoMasks) {
    checkImage(m, CV_8UC1, labels.size(), "M_geo");
    parts.push_back(part);
    masks.push_back(&m);
    area[part] = cv::countNonZero(m);
  }
  // region sizes and intersections with every part in one pass
  std::map<int, int> count;
  std::map<int, std::vector<int>> inter;
  for (int y = 0; y < labels.rows; ++y) {
    const int* pl = labels.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x) {
      const int l = pl[x];
      if (l == 0) continue;
      count[l]++;
      auto& row = inter.try_emplace(l, std::vector<int>(parts.size(), 0)).first->second;
      for (size_t k = 0; k < parts.size(); ++k)
        if (masks[k]->ptr<uint8_t>(y)[x]) row[k]++;
    }
  }
  MatchResult result;
  for (const auto& [label, n] : count) {
    RegionMatch r;
    r.label = label;
    r.pixels = n;
    const auto& row = inter[label];
    for (size_t k = 0; k < parts.size(); ++k) {
      const double u = n + area[parts[k]] - row[k];
      const double v = u > 0 ? row[k] / u : 0.0;
      if (v > r.iou) {
        r.iou = v;
        r.bestPart = parts[k];
      }
    }
    auto pin = pinned.find(label);
    if (pin != pinned.end()) {
      r.pinned = true;
      r.part = pin->second;
      auto k = std::find(parts.begin(), parts.end(), r.part);
      if (k != parts.end()) {
        const size_t i = k - parts.begin();
        r.iou = static_cast<double>(row[i]) / (n + area[r.part] - row[i]);
      } else {
        r.iou = 0;
      }
    } else if (r.bestPart >= 0 && r.iou >= options.minIou) {
      r.part = r.bestPart;
    }
    result.regions.push_back(r);
  }
  // the masks in one pass over the pixels (not one per region: a 16-bit label image may have
  // 65,535 regions)
  std::map<int, cv::Mat*> maskOf;
  for (const auto& r : result.regions) {
    if (r.part < 0) continue;
    maskOf[r.label] = &result.photoMasks.try_emplace(r.part, cv::Mat::zeros(labels.size(), CV_8UC1))
                           .first->second;
  }
  if (!maskOf.empty())
    for (int y = 0; y < labels.rows; ++y) {
      const int* pl = labels.ptr<int>(y);
      int last = 0;
      cv::Mat* lastMask = nullptr;
      for (int x = 0; x < labels.cols; ++x) {
        const int l = pl[x];
        if (l == 0) continue;
        if (l != last || !lastMask) {
          const auto it = maskOf.find(l);
          last = l;
          lastMask = it == maskOf.end() ? nullptr : it->second;
          if (!lastMask) continue;
        }
        lastMask->ptr<uint8_t>(y)[x] = 255;
      }
    }
  return result;
}

cv::Mat proposeRegions(const cv::Mat& photo, const std::map<int, cv::Mat>& geoMasks,
                       std::map<int, int>* pinned, const ProposalOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
  checkImage(photo, CV_32FC3, "photo");
  // SLIC on 8-bit Lab of the display-encoded photo (perceptual distances)
  cv::Mat srgb8 = linearToSrgb(photo, CV_8U), lab;
  cv::cvtColor(srgb8, lab, cv::COLOR_RGB2Lab);
  const double scale = std::sqrt(static_cast<double>(photo.total()) / (640.0 * 480.0));
  const int regionSize = std::max(12, static_cast<int>(std::lround(options.superpixelSize * scale)));
  auto slic = cv::ximgproc::createSuperpixelSLIC(lab, cv::ximgproc::SLICO, regionSize, options.ruler);
  slic->iterate(10);
  slic->enforceLabelConnectivity(25);
  cv::Mat sp;
  slic->getLabels(sp);
  const int n = slic->getNumberOfSuperpixels();
  std::vector<int> size(n, 0);
  std::vector<int> parts;
  for (const auto& [part, m] : geoMasks) {
    checkImage(m, CV_8UC1, photo.size(), "M_geo");
    parts.push_back(part);
  }
  std::vector<std::vector<int>> cover(n, std::vector<int>(parts.size(), 0));
  for (int y = 0; y < sp.rows; ++y) {
    const int* ps = sp.ptr<int>(y);
    for (int x = 0; x < sp.cols; ++x) {
      size[ps[x]]++;
      size_t k = 0;
      for (const auto& [part, m] : geoMasks) {
        if (m.ptr<uint8_t>(y)[x]) cover[ps[x]][k]++;
        ++k;
      }
    }
  }
  std::vector<int> assign(n, 0);
  for (int s = 0; s < n; ++s) {
    int best = -1, bestCount = 0;
    for (size_t k = 0; k < parts.size(); ++k)
      if (cover[s][k] > bestCount) {
        bestCount = cover[s][k];
        best = static_cast<int>(k);
      }
    if (best >= 0 && size[s] > 0 && bestCount >= options.minCoverage * size[s]) assign[s] = parts[best] + 1;
  }
  cv::Mat labels(sp.size(), CV_32SC1);
  for (int y = 0; y < sp.rows; ++y) {
    const int* ps = sp.ptr<int>(y);
    int* pl = labels.ptr<int>(y);
    for (int x = 0; x < sp.cols; ++x) pl[x] = assign[ps[x]];
  }
  pinned->clear();
  for (int part : parts) pinned->emplace(part + 1, part);
  return labels;
}

cv::Rect2d maskBox(const cv::Mat& mask) {
  checkImage(mask, CV_8UC1, "mask");
  const cv::Rect r = cv::boundingRect(mask);
  if (r.area() == 0) return cv::Rect2d();
  return cv::Rect2d(r.x - 0.5, r.y - 0.5, r.width, r.height);
}

cv::Matx23d boxAffine(const cv::Mat& geoMask, const cv::Mat& photoMask) {
  const cv::Rect2d g = maskBox(geoMask), p = maskBox(photoMask);
  PS_Check(g.area() > 0 && p.area() > 0, "boxAffine needs two non-empty masks");
  const double ax = g.width / p.width, ay = g.height / p.height;
  const double cgx = g.x + 0.5 * g.width, cgy = g.y + 0.5 * g.height;
  const double cpx = p.x + 0.5 * p.width, cpy = p.y + 0.5 * p.height;
  return cv::Matx23d(ax, 0, cgx - ax * cpx, 0, ay, cgy - ay * cpy);
}

AlignedPart alignPart(int part, const cv::Mat& geoMask, const cv::Mat& photoMask,
                      const std::vector<cv::Mat>& buffers) {
  checkImage(geoMask, CV_8UC1, "M_geo");
  checkImage(photoMask, CV_8UC1, "M_photo");
  AlignedPart out;
  out.part = part;
  out.photoPixels = cv::countNonZero(photoMask);
  out.mask = cv::Mat::zeros(photoMask.size(), CV_8UC1);
  if (out.photoPixels == 0 || cv::countNonZero(geoMask) == 0) {
    out.droppedPixels = out.photoPixels;
    for (const cv::Mat& b : buffers) out.buffers.push_back(cv::Mat::zeros(photoMask.size(), b.type()));
    return out;
  }
  out.photoToRender = boxAffine(geoMask, photoMask);
  const cv::Mat M(out.photoToRender);
  const int inverse = cv::WARP_INVERSE_MAP;
  cv::Mat geoNearest, geoLinear;
  cv::warpAffine(geoMask, geoNearest, M, photoMask.size(), cv::INTER_NEAREST | inverse, cv::BORDER_CONSTANT, 0);
  cv::warpAffine(geoMask, geoLinear, M, photoMask.size(), cv::INTER_LINEAR | inverse, cv::BORDER_CONSTANT, 0);
  out.mask = photoMask & geoNearest;
  out.droppedPixels = out.photoPixels - cv::countNonZero(out.mask);
  // where every bilinear neighbour lies inside M_geo, continuous buffers are interpolated;
  // elsewhere (part boundary) they take the nearest render pixel, never a value from outside
  const cv::Mat interior = geoLinear >= 255;
  for (const cv::Mat& b : buffers) {
    PS_CheckEQ(b.size(), geoMask.size(), "buffers must have M_geo's size");
    cv::Mat nearest;
    cv::warpAffine(b, nearest, M, photoMask.size(), cv::INTER_NEAREST | inverse, cv::BORDER_CONSTANT, 0);
    if (b.depth() == CV_32F || b.depth() == CV_64F) {
      cv::Mat linear;
      cv::warpAffine(b, linear, M, photoMask.size(), cv::INTER_LINEAR | inverse, cv::BORDER_CONSTANT, 0);
      linear.copyTo(nearest, interior);
    }
    nearest.setTo(0, ~out.mask);
    out.buffers.push_back(nearest);
  }
  return out;
}

UnwarpedTexture unwarpToTexture(const cv::Mat& photo, const cv::Mat& uv, const cv::Mat& mask,
                                const UnwarpOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
  checkImage(photo, CV_32FC3, "photo");
  checkImage(uv, CV_32FC2, photo.size(), "uv");
  checkImage(mask, CV_8UC1, photo.size(), "mask");
  UnwarpedTexture out;
  // pixel footprint in UV: lengths of the finite differences between masked neighbours
  std::vector<float> steps;
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  for (int y = 0; y < uv.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    const cv::Vec2f* p = uv.ptr<cv::Vec2f>(y);
    for (int x = 0; x < uv.cols; ++x) {
      if (!m[x] || !std::isfinite(p[x][0]) || !std::isfinite(p[x][1])) continue;
      u0 = std::min<double>(u0, p[x][0]);
      u1 = std::max<double>(u1, p[x][0]);
      v0 = std::min<double>(v0, p[x][1]);
      v1 = std::max<double>(v1, p[x][1]);
      if (x + 1 < uv.cols && m[x + 1]) steps.push_back(static_cast<float>(cv::norm(p[x + 1] - p[x])));
      if (y + 1 < uv.rows && mask.ptr<uint8_t>(y + 1)[x])
        steps.push_back(static_cast<float>(cv::norm(uv.ptr<cv::Vec2f>(y + 1)[x] - p[x])));
    }
  }
  if (!std::isfinite(u0)) {  // nothing to unwarp
    out.texture = cv::Mat::zeros(1, 1, CV_32FC3);
    out.coverage = cv::Mat::zeros(1, 1, CV_8UC1);
    return out;
  }
  double footprint = 0;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    footprint = steps[steps.size() / 2];
  }
  const double extent = std::max(u1 - u0, v1 - v0);
  double tpu = footprint > 1e-12 ? options.texelsPerPixel / footprint : 1.0;
  if (extent * tpu + 2 > options.maxSize) tpu = (options.maxSize - 2) / std::max(extent, 1e-12);
  if (!(tpu > 0) || !std::isfinite(tpu)) tpu = 1.0;
  const int w = std::max(1, static_cast<int>(std::ceil((u1 - u0) * tpu)) + 1);
  const int h = std::max(1, static_cast<int>(std::ceil((v1 - v0) * tpu)) + 1);
  cv::Mat accum = cv::Mat::zeros(h, w, CV_32FC3), weight = cv::Mat::zeros(h, w, CV_32FC1);
  for (int y = 0; y < uv.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    const cv::Vec2f* p = uv.ptr<cv::Vec2f>(y);
    const cv::Vec3f* c = photo.ptr<cv::Vec3f>(y);
    for (int x = 0; x < uv.cols; ++x) {
      if (!m[x] || !std::isfinite(p[x][0]) || !std::isfinite(p[x][1])) continue;
      const double tx = (p[x][0] - u0) * tpu, ty = (v1 - p[x][1]) * tpu;
      const int ix = static_cast<int>(std::floor(tx)), iy = static_cast<int>(std::floor(ty));
      const float fx = static_cast<float>(tx - ix), fy = static_cast<float>(ty - iy);
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx) {
          const int xx = ix + dx, yy = iy + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const float wgt = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
          accum.at<cv::Vec3f>(yy, xx) += wgt * c[x];
          weight.at<float>(yy, xx) += wgt;
        }
    }
  }
  out.texture = cv::Mat::zeros(h, w, CV_32FC3);
  out.coverage = cv::Mat::zeros(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float wt = weight.at<float>(y, x);
      if (wt > 0.25f) {
        out.texture.at<cv::Vec3f>(y, x) = accum.at<cv::Vec3f>(y, x) / wt;
        out.coverage.at<uint8_t>(y, x) = 255;
      }
    }
  out.uvMin = cv::Vec2d(u0, v0);
  out.uvMax = cv::Vec2d(u1, v1);
  out.texelsPerUv = tpu;
  return out;
}

cv::Mat sampleTexture(const UnwarpedTexture& t, const cv::Mat& uv, const cv::Mat& mask) {
  checkImage(uv, CV_32FC2, "uv");
  checkImage(mask, CV_8UC1, uv.size(), "mask");
  cv::Mat out = cv::Mat::zeros(uv.size(), CV_32FC3);
  const int w = t.texture.cols, h = t.texture.rows;
  for (int y = 0; y < uv.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    const cv::Vec2f* p = uv.ptr<cv::Vec2f>(y);
    cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
    for (int x = 0; x < uv.cols; ++x) {
      if (!m[x]) continue;
      const double tx = (p[x][0] - t.uvMin[0]) * t.texelsPerUv, ty = (t.uvMax[1] - p[x][1]) * t.texelsPerUv;
      const int ix = static_cast<int>(std::floor(tx)), iy = static_cast<int>(std::floor(ty));
      const float fx = static_cast<float>(tx - ix), fy = static_cast<float>(ty - iy);
      cv::Vec3f sum(0, 0, 0);
      float wsum = 0;
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx) {
          const int xx = ix + dx, yy = iy + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h || !t.coverage.at<uint8_t>(yy, xx)) continue;
          const float wgt = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
          sum += wgt * t.texture.at<cv::Vec3f>(yy, xx);
          wsum += wgt;
        }
      if (wsum > 1e-6f) o[x] = sum / wsum;
    }
  }
  return out;
}

cv::Vec3f maskedMedian(const cv::Mat& image, const cv::Mat& mask) {
  checkImage(image, CV_32FC3, "image");
  checkImage(mask, CV_8UC1, image.size(), "mask");
  std::vector<float> ch[3];
  for (int y = 0; y < image.rows; ++y) {
    const cv::Vec3f* p = image.ptr<cv::Vec3f>(y);
    const uint8_t* m = mask.ptr<uint8_t>(y);
    for (int x = 0; x < image.cols; ++x)
      if (m[x])
        for (int c = 0; c < 3; ++c) ch[c].push_back(p[x][c]);
  }
  cv::Vec3f out(0, 0, 0);
  for (int c = 0; c < 3; ++c) {
    if (ch[c].empty()) continue;
    std::nth_element(ch[c].begin(), ch[c].begin() + ch[c].size() / 2, ch[c].end());
    out[c] = ch[c][ch[c].size() / 2];
  }
  return out;
}

namespace {

double logLuminance(const cv::Vec3f& c, double exposure) {
  const double lum = luminance(static_cast<double>(c[0]), static_cast<double>(c[1]),
                               static_cast<double>(c[2]));
  return std::log(std::max(1e-4, lum / exposure));
}

double exposureOf(const std::vector<double>& exposure, int view) {
  return view >= 0 && view < static_cast<int>(exposure.size()) && exposure[view] > 0
             ? exposure[view]
             : 1.0;
}

/// The median (the mean of the two middle values for an even count).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

ViewChoice chooseView(const std::vector<PartObservation>& obs,
                      const std::vector<double>& exposure) {
  ViewChoice choice;
  if (obs.empty()) {
    choice.reason = "no view sees the part";
    return choice;
  }
  // the log median colours, exposure-corrected
  std::vector<cv::Vec3d> logColor;
  for (const auto& o : obs) {
    const double e = exposureOf(exposure, o.view);
    cv::Vec3d l;
    for (int c = 0; c < 3; ++c) l[c] = std::log(std::max(1e-4, o.medianColor[c] / e));
    logColor.push_back(l);
  }
  // the reference: median over views (three or more), the darker view (two)
  cv::Vec3d center(0, 0, 0);
  if (obs.size() > 2) {
    for (int c = 0; c < 3; ++c) {
      std::vector<double> v;
      for (const cv::Vec3d& l : logColor) v.push_back(l[c]);
      center[c] = median(v);
    }
  } else if (obs.size() == 2) {
    const bool firstDarker = logLuminance(obs[0].medianColor, exposureOf(exposure, obs[0].view)) <=
                             logLuminance(obs[1].medianColor, exposureOf(exposure, obs[1].view));
    center = logColor[firstDarker ? 0 : 1];
  }
  double best = -1;
  for (size_t i = 0; i < obs.size(); ++i) {
    const auto& o = obs[i];
    double d2 = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = logColor[i][c] - center[c];
      d2 += d * d / 3;
    }
    const double agreement = obs.size() > 1 ? std::exp(-d2 / (2 * 0.25 * 0.25)) : 1.0;
    const double score = o.pixels * std::max(0.0, o.meanCosine) * agreement;
    choice.scores.push_back(score);
    choice.agreement.push_back(agreement);
    if (score > best) {
      best = score;
      choice.view = o.view;
    }
  }
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "best of %zu views: score pixels x mean cos x appearance agreement = %.1f",
                obs.size(), best);
  choice.reason = buf;
  return choice;
}

std::vector<double> estimateExposures(const std::vector<std::vector<PartObservation>>& parts,
                                      int viewCount, int minPixels) {
  std::vector<double> logE(std::max(0, viewCount), 0.0);
  if (viewCount < 2) return std::vector<double>(logE.size(), 1.0);
  // per part seen (well enough) in two or more views: (view, log luminance)
  std::vector<std::vector<std::pair<int, double>>> seen;
  for (const auto& obs : parts) {
    std::vector<std::pair<int, double>> s;
    for (const PartObservation& o : obs)
      if (o.pixels >= minPixels && o.view >= 0 && o.view < viewCount)
        s.emplace_back(o.view, logLuminance(o.medianColor, 1.0));
    if (s.size() >= 2) seen.push_back(std::move(s));
  }
  if (seen.empty()) return std::vector<double>(logE.size(), 1.0);
  // Least squares first (alternating means: its fixed point is unique and moves with the data,
  // so scaling one photo moves only its exposure), then medians from there (robust to a
  // highlight); every step commutes with scaling a photo, so the result does too.
  std::vector<double> logAlbedo(seen.size(), 0.0);
  auto center = [](const std::vector<double>& r, bool robust) {
    if (robust) return median(r);
    double sum = 0;
    for (double x : r) sum += x;
    return sum / static_cast<double>(r.size());
  };
  for (int it = 0; it < 200; ++it) {
    const bool robust = it >= 150;
    for (size_t p = 0; p < seen.size(); ++p) {
      std::vector<double> r;
      for (const auto& [v, l] : seen[p]) r.push_back(l - logE[v]);
      logAlbedo[p] = center(r, robust);
    }
    for (int v = 1; v < viewCount; ++v) {
      std::vector<double> r;
      for (size_t p = 0; p < seen.size(); ++p)
        for (const auto& [w, l] : seen[p])
          if (w == v) r.push_back(l - logAlbedo[p]);
      if (!r.empty()) logE[v] = center(r, robust);
    }
  }
  std::vector<double> e;
  for (double l : logE) e.push_back(std::exp(l));
  return e;
}

}  // namespace ps::align
