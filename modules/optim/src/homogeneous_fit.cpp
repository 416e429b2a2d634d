#include "photoscene/optim/homogeneous_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "photoscene/core/log.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/optim/part_fit.hpp"
#include "photoscene/optim/roughness_prior.hpp"

namespace ps {

namespace {
cv::Mat constantMap(const Vec3f& v) {
  return cv::Mat(4, 4, CV_32FC3, cv::Scalar(v.x(), v.y(), v.z()));
}

/// Sum over the views' pixels of min(i0 + a d, clip) in channel k.
double clippedSum(const std::vector<PartView>& views, const std::vector<cv::Mat>& i0,
                  const std::vector<cv::Mat>& d, int k, double a) {
  double s = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    const double clip = views[v].clip;
    for (const cv::Point& q : views[v].geometry->pixels)
      s += std::min(double(i0[v].at<cv::Vec3f>(q)[k]) + a * d[v].at<cv::Vec3f>(q)[k], clip);
  }
  return s;
}

/// The coefficient a of a render i0 + a d (per view; d >= 0) whose sum over the views' pixels,
/// clipped at each view's PartView::clip, is the photo's `photoSum` in channel k (file comment).
/// `linear` is the unclipped solution, a lower bound (clipping only lowers the sum). Returns
/// `linear` where no render pixel reaches a finite clip or its clipped sum already suffices;
/// above the search's reach (64) where the photo's sum cannot be reached (the caller clamps).
double censoredSolve(const std::vector<PartView>& views, const std::vector<cv::Mat>& i0,
                     const std::vector<cv::Mat>& d, int k, double photoSum, double linear) {
  bool reaches = false;  // does the render at the linear solution reach a clip level anywhere?
  for (size_t v = 0; v < views.size() && !reaches; ++v) {
    if (!std::isfinite(views[v].clip)) continue;
    for (const cv::Point& q : views[v].geometry->pixels)
      if (i0[v].at<cv::Vec3f>(q)[k] + linear * d[v].at<cv::Vec3f>(q)[k] > views[v].clip) {
        reaches = true;
        break;
      }
  }
  if (!reaches || clippedSum(views, i0, d, k, linear) >= photoSum) return linear;
  // the clipped sum grows with a (no faster than the unclipped one): bracket, then bisect
  double lo = linear, hi = std::max(2.0 * lo, 1e-3);
  while (clippedSum(views, i0, d, k, hi) < photoSum) {
    lo = hi;
    hi *= 2;
    if (hi > 64) return hi;  // the photo's sum is out of reach
  }
  for (int it = 0; it < 40 && hi - lo > 1e-6 * std::abs(hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    (clippedSum(views, i0, d, k, mid) < photoSum ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace

std::vector<float> roughnessGrid(int n) {
  std::vector<float> r;
  for (int i = 0; i < n; ++i) r.push_back(0.15f + 0.8f * i / std::max(1, n - 1));
  return r;
}

std::optional<HomogeneousRoughness> homogeneousRoughness(const PartFitOptions& options) {
  if (options.roughnessPriorWeight <= 0 && options.highlightWeight <= 0) return std::nullopt;
  HomogeneousRoughness r;
  r.prior = roughnessPriorFor("");
  r.priorWeight = options.roughnessPriorWeight;
  r.highlightWeight = options.highlightWeight;
  r.highlight = options.highlight;
  return r;
}

HomogeneousFit fitHomogeneous(const PartGeometry& geo, const cv::Mat& photo,
                              const std::vector<float>& grid,
                              const std::optional<HomogeneousRoughness>& rough) {
  return fitHomogeneous(std::vector<PartView>{{&geo, photo}}, grid, rough);
}

HomogeneousFit fitHomogeneous(const std::vector<PartView>& views, const std::vector<float>& grid,
                              const std::optional<HomogeneousRoughness>& rough) {
  PS_Check(!views.empty(), "fitHomogeneous: no view");
  for (const PartView& v : views) PS_Check(v.geometry, "fitHomogeneous: a view without geometry");
  const PartGeometry& first = *views.front().geometry;
  std::vector<float> roughnesses = grid;
  std::vector<std::vector<cv::Point>> highlight(views.size());
  bool anyHighlight = false;
  if (rough) {
    for (size_t v = 0; v < views.size(); ++v) {
      highlight[v] = highlightRegion(*views[v].geometry, rough->highlight);
      anyHighlight = anyHighlight || !highlight[v].empty();
    }
    if (!anyHighlight) {
      roughnesses = {std::clamp(rough->prior.center(), rough->prior.min, rough->prior.max)};
    } else {
      for (float& r : roughnesses) r = std::clamp(r, rough->prior.min, rough->prior.max);
      std::sort(roughnesses.begin(), roughnesses.end());
      roughnesses.erase(std::unique(roughnesses.begin(), roughnesses.end()), roughnesses.end());
    }
  }
  HomogeneousFit best;
  best.loss = std::numeric_limits<double>::infinity();
  double bestScore = std::numeric_limits<double>::infinity();
  double pixels = 0;
  cv::Scalar photoSum(0, 0, 0);
  for (const PartView& v : views) {
    for (const cv::Point& q : v.geometry->pixels) {
      const cv::Vec3f c = v.photo.at<cv::Vec3f>(q);
      for (int k = 0; k < 3; ++k) photoSum[k] += c[k];
    }
    pixels += static_cast<double>(v.geometry->pixels.size());
  }
  const double n = std::max(1.0, pixels);
  for (float r : roughnesses) {
    // per view: the specular part i0 (no albedo) and the diffuse response d to a white albedo
    std::vector<cv::Mat> i0(views.size()), d(views.size());
    cv::Scalar s0(0, 0, 0), sd(0, 0, 0);
    for (size_t v = 0; v < views.size(); ++v) {
      RenderLayerParams p;
      p.geometry = views[v].geometry;
      p.roughnessValue = r;
      p.albedo = constantMap(Vec3f::Zero());
      renderLayerForward(p);
      i0[v] = p.image.clone();
      p.albedo = constantMap(Vec3f::Ones());
      renderLayerForward(p);
      d[v] = p.image - i0[v];
      for (const cv::Point& q : views[v].geometry->pixels) {
        const cv::Vec3f a = i0[v].at<cv::Vec3f>(q), b = d[v].at<cv::Vec3f>(q);
        for (int k = 0; k < 3; ++k) {
          s0[k] += a[k];
          sd[k] += b[k];
        }
      }
    }
    Vec3f albedo;
    for (int k = 0; k < 3; ++k) {
      const double diffuse = sd[k] / n;
      albedo[k] = diffuse > 1e-9 ? static_cast<float>((photoSum[k] - s0[k]) / n / diffuse) : 0.5f;
      if (diffuse > 1e-9 && albedo[k] > 0)
        albedo[k] = static_cast<float>(censoredSolve(views, i0, d, k, photoSum[k], albedo[k]));
    }
    const float over = albedo.maxCoeff();
    albedo = albedo.cwiseMax(0.0f).cwiseMin(1.0f);
    double loss = 0, hl = 0;
    for (size_t v = 0; v < views.size(); ++v) {
      const PartGeometry& g = *views[v].geometry;
      const cv::Mat render = i0[v] + d[v].mul(cv::Scalar(albedo.x(), albedo.y(), albedo.z()));
      const double w = static_cast<double>(g.pixels.size()) / n;
      loss += w * statLoss(views[v].photo, render, g.pixels, nullptr);
      if (rough && !highlight[v].empty())
        hl += w * highlightLoss(views[v].photo, render, g.pixels, highlight[v], nullptr);
    }
    // with the roughness terms, the highlight and the prior alone rank the candidates: the
    // statistics of a flat material's render fall with its roughness whatever the photo shows
    // (a matte floor, truth 0.75: statLoss 0.09 at 0.15 rising to 0.24 at 0.95)
    const double score =
        rough && anyHighlight
            ? rough->highlightWeight * hl + rough->priorWeight * roughnessPriorLoss(rough->prior, r, nullptr)
            : loss;
    if (score < bestScore) {
      bestScore = score;
      best = {albedo, r, loss, over > 1.0f, over};
    }
  }
  if (best.albedoClamped)
    spdlog::warn(
        "fitHomogeneous (part {}): the albedo that matches the photo is {:.2f} > 1 in a channel, "
        "clamped to 1: light and albedo traded against each other (the part's light is too dim)",
        first.part, best.unclampedMax);
  return best;
}

TexturedRefine refineTextured(const PartGeometry& geo, const cv::Mat& photo, const cv::Mat& mask,
                              const cv::Mat& albedo, const cv::Mat& normal, const UvParams& uv,
                              float roughness, int n, float clip) {
  TexturedRefine best;
  // the roughness factor moves only where the light predicts a highlight (else the photo has
  // nothing to say about gloss and the statistics prefer a sparkle that matches noise); there the
  // highlight contrast joins the statistics (optim/roughness_prior.hpp)
  const std::vector<cv::Point> highlight = highlightRegion(geo);
  if (highlight.empty()) n = 1;
  best.loss = std::numeric_limits<double>::infinity();
  for (int c = 0; c < n; ++c) {
    const float factor =
        n == 1 ? 1.0f : std::exp(std::log(0.5f) + (std::log(2.0f) - std::log(0.5f)) * c / (n - 1));
    RenderLayerParams rp;
    rp.geometry = &geo;
    rp.uv = uv;
    rp.normal = normal;
    rp.roughnessValue = std::clamp(roughness * factor, 0.02f, 1.0f);
    rp.albedo = cv::Mat::zeros(albedo.size(), CV_32FC3);
    renderLayerForward(rp);
    const cv::Mat i0 = rp.image.clone();
    rp.albedo = albedo;
    renderLayerForward(rp);
    const cv::Mat d = rp.image - i0;
    rp.albedo = cv::Mat(albedo.size(), CV_32FC3, cv::Scalar::all(1));
    renderLayerForward(rp);
    const cv::Mat w = rp.image - i0;  // the diffuse response to a white albedo
    // the render is linear in the albedo (a dielectric): i0 + s (d + o (.) w) for the contract's
    // albedo = s (map + o). One scale s by least squares on the channel means, then the
    // per-channel offset o that matches each channel's mean: the pattern keeps its contrast, the
    // colour comes out right even where the graph's colour parameters could not reach it.
    double num = 0, den = 0;
    const cv::Scalar mp = cv::mean(photo, mask), m0 = cv::mean(i0, mask), md = cv::mean(d, mask),
                     mw = cv::mean(w, mask);
    for (int k = 0; k < 3; ++k) {
      num += (mp[k] - m0[k]) * md[k];
      den += md[k] * md[k];
    }
    const float s = den > 1e-12 ? std::clamp(static_cast<float>(num / den), 0.25f, 4.0f) : 1.0f;
    Vec3f o = Vec3f::Zero();
    for (int k = 0; k < 3; ++k)
      if (mw[k] > 1e-9)
        o[k] =
            std::clamp(static_cast<float>((mp[k] - m0[k] - s * md[k]) / (s * mw[k])), -0.5f, 0.5f);
    if (std::isfinite(clip)) {
      // where the photo clips, each channel's offset matches its mean with the render clipped:
      // the render is (i0 + s d) + o (s w), the censored solve's form in o (bounded at 0.5)
      const std::vector<PartView> view = {{&geo, photo, clip}};
      const std::vector<cv::Mat> base = {i0 + d * s}, slope = {w * s};
      double photoSum[3] = {0, 0, 0};
      for (const cv::Point& q : geo.pixels)
        for (int k = 0; k < 3; ++k) photoSum[k] += photo.at<cv::Vec3f>(q)[k];
      for (int k = 0; k < 3; ++k)
        if (mw[k] > 1e-9)
          o[k] = std::min(0.5f, static_cast<float>(censoredSolve(view, base, slope, k, photoSum[k], o[k])));
    }
    const cv::Mat render = i0 + (d + w.mul(cv::Scalar(o.x(), o.y(), o.z()))) * s;
    const double loss = statLoss(photo, render, geo.pixels, nullptr) +
                        highlightLoss(photo, render, geo.pixels, highlight, nullptr);
    if (loss < best.loss) {
      best.loss = loss;
      best.albedoScale = s;
      best.albedoOffset = o;
      best.roughnessFactor = rp.roughnessValue / std::max(roughness, 1e-4f);
    }
  }
  return best;
}

Vec3f shadingMedianAlbedo(const PartGeometry& geo, const cv::Mat& photo) {
  RenderLayerParams rp;
  rp.geometry = &geo;
  rp.roughnessValue = 1.0f;
  rp.specular = 0.0f;  // pure Lambert shading
  rp.albedo = constantMap(Vec3f::Ones());
  renderLayerForward(rp);
  std::vector<float> ratio[3];
  for (const cv::Point& q : geo.pixels) {
    const cv::Vec3f s = rp.image.at<cv::Vec3f>(q), c = photo.at<cv::Vec3f>(q);
    for (int k = 0; k < 3; ++k)
      if (s[k] > 1e-6f) ratio[k].push_back(c[k] / s[k]);
  }
  Vec3f albedo;
  for (int k = 0; k < 3; ++k) {
    if (ratio[k].empty()) {
      albedo[k] = 0.5f;
      continue;
    }
    std::nth_element(ratio[k].begin(), ratio[k].begin() + ratio[k].size() / 2, ratio[k].end());
    albedo[k] = std::clamp(ratio[k][ratio[k].size() / 2], 0.0f, 1.0f);
  }
  return albedo;
}

}  // namespace ps
