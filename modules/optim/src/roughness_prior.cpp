#include "photoscene/optim/roughness_prior.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "photoscene/core/error.hpp"

namespace ps {

namespace {

RoughnessPrior makePrior(const std::string& category, float center, float logSigma, float lo) {
  RoughnessPrior p;
  p.category = category;
  p.logMean = std::log(center);
  p.logSigma = logSigma;
  p.min = lo;
  p.max = 1.0f;
  return p;
}

// The table (modules/optim/README.md, "Roughness priors"). Measured: the geometric mean of the
// roughness-map means of the category's materials in the yardstick's `tune` half (the check half
// is not looked at), sigma their standard deviation in ln r with a floor of 0.25 (1-2 materials
// say little about the spread). Assumed (no tune material with a roughness map): stated per row.
// The lower bounds: the lowest tune value of the category with a margin, and "never glossy" for
// the fibrous and porous categories.
const std::map<std::string, RoughnessPrior>& table() {
  static const std::map<std::string, RoughnessPrior> t = [] {
    std::map<std::string, RoughnessPrior> m;
    auto add = [&](const char* c, float center, float sigma, float lo) {
      m[c] = makePrior(c, center, sigma, lo);
    };
    add("brick", 0.924f, 0.25f, 0.50f);     // 2: brick_pavement_03 0.938, brick_wall_001 0.911
    add("carpet", 0.726f, 0.25f, 0.50f);    // 2: carpet016 0.648, dirty_carpet 0.813 (sd 0.16)
    add("concrete", 0.658f, 0.30f, 0.30f);  // 4: 0.507-0.926 (sd 0.30)
    add("fabric", 0.729f, 0.25f, 0.45f);    // 1: fabric030 0.729; never glossy
    add("metal", 0.375f, 0.74f,
        0.05f);  // 3: metal007 0.159, metalplates013 0.565, metal_plate 0.589
    add("plaster", 0.777f, 0.25f, 0.35f);  // 5: 0.513-0.919 (sd 0.24)
    add("stone", 0.314f, 1.06f,
        0.04f);  // 6: marbles 0.066-0.369, paving 0.502, sandstones 0.82-0.84
    add("tile", 0.294f, 0.60f, 0.04f);  // 1: tiles036 0.294; sigma assumed (glazed to matte)
    add("wood", 0.265f, 0.69f, 0.05f);  // 4: herringbone 0.098, woodfloor043 0.284, 0.402, 0.440
    // assumed (no tune material with a roughness map)
    add("paint", 0.777f, 0.30f, 0.25f);     // as plaster (painted plaster), a little wider
    add("wallpaper", 0.75f, 0.30f, 0.35f);  // paper-like, matte
    add("paper", 0.80f, 0.25f, 0.45f);      // fibrous: never glossy
    add("cork", 0.80f, 0.25f, 0.45f);       // porous: never glossy
    add("rubber", 0.70f, 0.30f, 0.30f);
    add("leather", 0.55f, 0.40f, 0.20f);  // waxed leather can shine a little
    add("plastic", 0.40f, 0.60f, 0.05f);
    return m;
  }();
  return t;
}

}  // namespace

float RoughnessPrior::center() const {
  return std::exp(logMean);
}

RoughnessPrior roughnessPriorFor(const std::string& category) {
  const auto& t = table();
  const auto it = t.find(category);
  if (it != t.end()) return it->second;
  // generic: all 28 tune materials with a roughness map, geometric mean 0.481, sd of ln r 0.733
  return makePrior(category, 0.481f, 0.733f, 0.04f);
}

double roughnessPriorLoss(const RoughnessPrior& prior, float roughness, double* grad) {
  const double r = std::max(1e-4, static_cast<double>(roughness));
  const double s = std::max(1e-3, static_cast<double>(prior.logSigma));
  const double z = (std::log(r) - prior.logMean) / s;
  if (grad) *grad = roughness > 1e-4f ? z / (s * r) : 0.0;
  return 0.5 * z * z;
}

std::vector<cv::Point> highlightRegion(const PartGeometry& geo, const HighlightOptions& o) {
  std::vector<cv::Point> out;
  if (geo.size() == 0) return out;
  RenderLayerParams p;
  p.geometry = &geo;
  p.roughnessValue = o.glossyRoughness;
  p.specularSub = 2;
  p.albedo = cv::Mat(4, 4, CV_32FC3, cv::Scalar::all(0.0));
  renderLayerForward(p);
  const cv::Mat spec = p.image.clone();
  p.albedo = cv::Mat(4, 4, CV_32FC3, cv::Scalar::all(1.0));
  p.specular = 0.0f;
  renderLayerForward(p);
  const cv::Mat& diffuse = p.image;
  for (const cv::Point& q : geo.pixels) {
    const cv::Vec3f s = spec.at<cv::Vec3f>(q), d = diffuse.at<cv::Vec3f>(q);
    const float ls = s[0] + s[1] + s[2], ld = d[0] + d[1] + d[2];
    if (std::isfinite(ls) && ld > 0 && ls > o.minRatio * ld) out.push_back(q);
  }
  const double n = geo.size();
  if (static_cast<int>(out.size()) < o.minPixels || out.size() < o.minFraction * n ||
      out.size() > o.maxFraction * n)
    out.clear();
  return out;
}

double highlightLoss(const cv::Mat& photo, const cv::Mat& render,
                     const std::vector<cv::Point>& pixels, const std::vector<cv::Point>& highlight,
                     cv::Mat* grad, double weight) {
  if (highlight.empty() || pixels.empty()) return 0.0;
  auto sum = [](const cv::Mat& im, const std::vector<cv::Point>& px) {
    double s = 0;
    for (const cv::Point& q : px) {
      const cv::Vec3f v = im.at<cv::Vec3f>(q);
      s += static_cast<double>(v[0]) + v[1] + v[2];
    }
    return s / (3.0 * px.size());
  };
  // eps: a tiny fraction of the photo's level, so black parts give a finite 0
  const double mPa = sum(photo, pixels), mPh = sum(photo, highlight);
  const double eps = 1e-3 * std::max(mPa, 1e-6) + 1e-9;
  const double mRa = sum(render, pixels), mRh = sum(render, highlight);
  const double cP = std::log(std::max(0.0, mPh) + eps) - std::log(std::max(0.0, mPa) + eps);
  const double cR = std::log(std::max(0.0, mRh) + eps) - std::log(std::max(0.0, mRa) + eps);
  const double d = cP - cR;
  if (!std::isfinite(d)) return 0.0;
  if (grad) {
    if (grad->empty()) *grad = cv::Mat::zeros(render.size(), CV_32FC3);
    // dL/dcR = -2 d; dcR/dR_i = [i in H] / (3 nH (mRh + eps)) - 1 / (3 n (mRa + eps)) per channel
    const double gAll = weight * 2.0 * d / (3.0 * pixels.size() * (std::max(0.0, mRa) + eps));
    const double gHl = -weight * 2.0 * d / (3.0 * highlight.size() * (std::max(0.0, mRh) + eps));
    for (const cv::Point& q : pixels)
      grad->at<cv::Vec3f>(q) += cv::Vec3f::all(static_cast<float>(gAll));
    for (const cv::Point& q : highlight)
      grad->at<cv::Vec3f>(q) += cv::Vec3f::all(static_cast<float>(gHl));
  }
  return d * d;
}

double albedoCeilingLoss(const cv::Mat& albedo, float knee, cv::Mat* grad, double weight) {
  PS_Check(albedo.type() == CV_32FC3, "albedoCeilingLoss: albedo must be CV_32FC3");
  PS_Check(knee > 0 && knee < 1, "albedoCeilingLoss: knee must be in (0, 1)");
  if (albedo.empty()) return 0.0;
  if (grad && grad->empty()) *grad = cv::Mat::zeros(albedo.size(), CV_32FC3);
  const double n = 3.0 * albedo.total(), w = 1.0 / (1.0 - knee);
  double l = 0;
  for (int y = 0; y < albedo.rows; ++y)
    for (int x = 0; x < albedo.cols; ++x) {
      const cv::Vec3f a = albedo.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) {
        if (!(a[c] > knee)) continue;  // NaN-safe
        const double e = (a[c] - knee) * w;
        l += e * e;
        if (grad) grad->at<cv::Vec3f>(y, x)[c] += static_cast<float>(weight * 2.0 * e * w / n);
      }
    }
  return l / n;
}

cv::Vec3f albedoFractionAtCeiling(const cv::Mat& albedo, float level) {
  cv::Vec3f f(0, 0, 0);
  if (albedo.empty()) return f;
  for (int y = 0; y < albedo.rows; ++y)
    for (int x = 0; x < albedo.cols; ++x) {
      const cv::Vec3f a = albedo.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c) f[c] += a[c] >= level ? 1.0f : 0.0f;
    }
  return f / static_cast<float>(albedo.total());
}

}  // namespace ps
