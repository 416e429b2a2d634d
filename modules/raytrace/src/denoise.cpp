#include "photoscene/raytrace/denoise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "photoscene/core/parallel.hpp"
#include "photoscene/core/color.hpp"

namespace ps {

namespace {

inline float finitePositive(float v) {
  return std::isfinite(v) && v > 0.0f ? v : 0.0f;
}

constexpr float kB3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};

void checkGuide(const cv::Mat& m, int type, const cv::Size& size, const char* name) {
  if (m.type() != type || m.size() != size)
    throw std::invalid_argument(std::string("ps::denoise: guide '") + name + "' must be " +
                                (type == CV_32FC3 ? "CV_32FC3" : "CV_32FC1") +
                                " of the noisy image's size " + std::to_string(size.width) + "x" +
                                std::to_string(size.height));
}

}  // namespace

bool DenoiseOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* what) {
    if (error) *error = what;
    return false;
  };
  if (levels < 0 || levels > 12) return fail("levels must be in [0, 12]");
  if (!(sigmaLuminance > 0)) return fail("sigmaLuminance must be > 0");
  if (!(sigmaNormal >= 0)) return fail("sigmaNormal must be >= 0");
  if (!(sigmaDepth > 0)) return fail("sigmaDepth must be > 0");
  if (!(albedoEpsilon > 0 && albedoEpsilon <= 1)) return fail("albedoEpsilon must be in (0, 1]");
  return true;
}

namespace {

/// The image being filtered, one entry per pixel (row-major): the demodulated radiance and its
/// luminance variance, which each a-trous level replaces, and the guides.
struct Frame {
  int W = 0, H = 0;
  std::vector<cv::Vec3f> demod, albedo, normal;
  std::vector<float> depth, gradZ, var;
  std::vector<uint8_t> surface;  ///< the depth guide shows a surface (finite, positive)
  size_t at(int x, int y) const { return size_t(y) * W + x; }
};

/// Radiance divided by the albedo (clamped to [albedoEpsilon, 1]); NaN and negative values of
/// every input -> 0 (a NaN albedo -> 1, a pixel without a surface keeps depth 0).
Frame demodulate(const DenoiseGuides& g, const cv::Mat& noisy, const DenoiseOptions& o) {
  Frame f;
  f.W = noisy.cols;
  f.H = noisy.rows;
  const size_t N = size_t(f.W) * f.H;
  f.demod.resize(N);
  f.albedo.resize(N);
  f.normal.resize(N);
  f.depth.resize(N);
  f.gradZ.assign(N, 0.0f);
  f.var.assign(N, 0.0f);
  f.surface.resize(N);
  parallelFor(0, f.H, [&](int64_t y) {
    for (int x = 0; x < f.W; ++x) {
      const size_t i = f.at(x, int(y));
      const cv::Vec3f c = noisy.at<cv::Vec3f>(int(y), x);
      const cv::Vec3f a = g.albedo.at<cv::Vec3f>(int(y), x);
      const float z = g.depth.at<float>(int(y), x);
      f.surface[i] = std::isfinite(z) && z > 0.0f;
      f.depth[i] = f.surface[i] ? z : 0.0f;
      cv::Vec3f n = g.normal.at<cv::Vec3f>(int(y), x);
      for (int k = 0; k < 3; ++k) n[k] = std::isfinite(n[k]) ? n[k] : 0.0f;
      f.normal[i] = n;
      for (int k = 0; k < 3; ++k) {
        f.albedo[i][k] =
            std::max(std::isfinite(a[k]) ? std::min(a[k], 1.0f) : 1.0f, o.albedoEpsilon);
        f.demod[i][k] = finitePositive(c[k]) / f.albedo[i][k];
      }
    }
  });
  return f;
}

/// Depth gradient (px^-1) per surface pixel: per axis the smaller one-sided difference to a
/// surface neighbour (a depth edge next to the pixel is not its slope).
void depthGradient(Frame& f) {
  parallelFor(0, f.H, [&](int64_t y) {
    for (int x = 0; x < f.W; ++x) {
      const size_t i = f.at(x, int(y));
      if (!f.surface[i]) continue;
      auto slope = [&](int dx, int dy) {
        float s = std::numeric_limits<float>::infinity();
        for (int sgn : {-1, 1}) {
          const int xx = x + sgn * dx, yy = int(y) + sgn * dy;
          if (xx < 0 || yy < 0 || xx >= f.W || yy >= f.H) continue;
          const size_t j = f.at(xx, yy);
          if (!f.surface[j]) continue;
          s = std::min(s, std::abs(f.depth[j] - f.depth[i]));
        }
        return std::isfinite(s) ? s : 0.0f;
      };
      const float gx = slope(1, 0), gy = slope(0, 1);
      f.gradZ[i] = std::sqrt(gx * gx + gy * gy);
    }
  });
}

/// The demodulated luminance's variance before filtering: the renderer's per-pixel variance
/// divided by the albedo's luminance squared where given, else a spatial estimate (the variance
/// over the 5x5 neighbours on the same surface: normal within ~25 degrees, depth on the local
/// plane).
void initialVariance(Frame& f, const cv::Mat& variance) {
  if (!variance.empty()) {
    parallelFor(0, f.H, [&](int64_t y) {
      for (int x = 0; x < f.W; ++x) {
        const size_t i = f.at(x, int(y));
        const float la = luminance(f.albedo[i]);
        f.var[i] = finitePositive(variance.at<float>(int(y), x)) / (la * la);
      }
    });
    return;
  }
  parallelFor(0, f.H, [&](int64_t y) {
    for (int x = 0; x < f.W; ++x) {
      const size_t i = f.at(x, int(y));
      if (!f.surface[i]) continue;
      double s = 0, s2 = 0;
      int n = 0;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int xx = x + dx, yy = int(y) + dy;
          if (xx < 0 || yy < 0 || xx >= f.W || yy >= f.H) continue;
          const size_t j = f.at(xx, yy);
          if (!f.surface[j] || f.normal[i].dot(f.normal[j]) < 0.9f) continue;
          const float r = std::sqrt(float(dx * dx + dy * dy));
          if (std::abs(f.depth[j] - f.depth[i]) > 2.0f * f.gradZ[i] * r + 1e-2f * f.depth[i])
            continue;
          const double l = luminance(f.demod[j]);
          s += l;
          s2 += l * l;
          ++n;
        }
      f.var[i] = n > 1 ? float(std::max(0.0, (s2 - s * s / n) / (n - 1))) : 0.0f;
    }
  });
}

/// 3x3 Gaussian of the variance over surface pixels, for the luminance edge-stop (SVGF).
void blurVariance(const Frame& f, std::vector<float>& out) {
  parallelFor(0, f.H, [&](int64_t y) {
    for (int x = 0; x < f.W; ++x) {
      const size_t i = f.at(x, int(y));
      if (!f.surface[i]) continue;
      float s = 0, ws = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = int(y) + dy;
          if (xx < 0 || yy < 0 || xx >= f.W || yy >= f.H) continue;
          const size_t j = f.at(xx, yy);
          if (!f.surface[j]) continue;
          const float w = (dx ? 0.5f : 1.0f) * (dy ? 0.5f : 1.0f);
          s += w * f.var[j];
          ws += w;
        }
      out[i] = s / ws;
    }
  });
}

/// One a-trous level (taps `step` pixels apart, B3 spline weights) with the normal, depth and
/// luminance edge-stops: f.demod and f.var replaced by the filtered values (`next`, `nextVar`
/// and `varBlur` are scratch of the frame's size).
void atrousLevel(Frame& f, int step, const DenoiseOptions& o, std::vector<cv::Vec3f>& next,
                 std::vector<float>& nextVar, std::vector<float>& varBlur) {
  blurVariance(f, varBlur);
  parallelFor(0, f.H, [&](int64_t y) {
    for (int x = 0; x < f.W; ++x) {
      const size_t i = f.at(x, int(y));
      if (!f.surface[i]) {
        next[i] = f.demod[i];
        nextVar[i] = f.var[i];
        continue;
      }
      const float lp = luminance(f.demod[i]);
      const float lumDenom = o.sigmaLuminance * std::sqrt(varBlur[i]) + 1e-6f;
      const cv::Vec3f np = f.normal[i];
      const float zp = f.depth[i];
      cv::Vec3f sum(0, 0, 0);
      float wsum = 0, vsum = 0;
      for (int ky = 0; ky < 5; ++ky) {
        const int yy = int(y) + (ky - 2) * step;
        if (yy < 0 || yy >= f.H) continue;
        for (int kx = 0; kx < 5; ++kx) {
          const int xx = x + (kx - 2) * step;
          if (xx < 0 || xx >= f.W) continue;
          const size_t j = f.at(xx, yy);
          if (!f.surface[j]) continue;
          float w = kB3[kx] * kB3[ky];
          if (j != i) {
            const float nd = std::max(0.0f, np.dot(f.normal[j]));
            const float wn = o.sigmaNormal > 0 ? std::pow(nd, o.sigmaNormal) : 1.0f;
            const float off = step * std::sqrt(float((kx - 2) * (kx - 2) + (ky - 2) * (ky - 2)));
            const float wz = std::exp(-std::abs(zp - f.depth[j]) /
                                      (o.sigmaDepth * f.gradZ[i] * off + 1e-3f * zp));
            const float wl = std::exp(-std::abs(lp - luminance(f.demod[j])) / lumDenom);
            w *= wn * wz * wl;
          }
          sum += w * f.demod[j];
          wsum += w;
          vsum += w * w * f.var[j];
        }
      }
      // wsum >= kB3[2]^2 > 0: the center tap always counts.
      next[i] = sum / wsum;
      nextVar[i] = vsum / (wsum * wsum);
    }
  });
  f.demod.swap(next);
  f.var.swap(nextVar);
}

/// The filtered radiance times the albedo again (NaN and negative -> 0).
cv::Mat remodulate(const Frame& f) {
  cv::Mat out(f.H, f.W, CV_32FC3);
  parallelFor(0, f.H, [&](int64_t y) {
    for (int x = 0; x < f.W; ++x) {
      const size_t i = f.at(x, int(y));
      cv::Vec3f c;
      for (int k = 0; k < 3; ++k) c[k] = finitePositive(f.demod[i][k] * f.albedo[i][k]);
      out.at<cv::Vec3f>(int(y), x) = c;
    }
  });
  return out;
}

}  // namespace

cv::Mat denoise(const DenoiseGuides& g, const cv::Mat& noisy, const DenoiseOptions& o) {
  std::string err;
  if (!o.IsValid(&err)) throw std::invalid_argument("ps::denoise: " + err);
  if (noisy.type() != CV_32FC3)
    throw std::invalid_argument("ps::denoise: the noisy image must be CV_32FC3");
  const cv::Size size = noisy.size();
  checkGuide(g.albedo, CV_32FC3, size, "albedo");
  checkGuide(g.normal, CV_32FC3, size, "normal");
  checkGuide(g.depth, CV_32FC1, size, "depth");
  if (!g.variance.empty()) checkGuide(g.variance, CV_32FC1, size, "variance");
  const size_t N = size_t(size.width) * size.height;
  if (N == 0) return cv::Mat(size, CV_32FC3);

  Frame f = demodulate(g, noisy, o);
  depthGradient(f);
  initialVariance(f, g.variance);
  std::vector<cv::Vec3f> next(N);
  std::vector<float> nextVar(N), varBlur(N);
  for (int level = 0; level < o.levels; ++level)
    atrousLevel(f, 1 << level, o, next, nextVar, varBlur);
  return remodulate(f);
}

DenoiseGuides denoiseGuides(const PathTracer& tracer, const GBuffer& gb) {
  DenoiseGuides g;
  const cv::Size size = gb.partId.size();
  g.albedo.create(size, CV_32FC3);
  g.normal = gb.normalShading.clone();
  g.depth = gb.depth.clone();
  parallelFor(0, size.height, [&](int64_t y) {
    for (int x = 0; x < size.width; ++x) {
      const int part = gb.partId.at<int>(int(y), x);
      cv::Vec3f a(1, 1, 1);
      if (part >= 0 && !tracer.isWindowPart(part)) {
        const cv::Vec2f uv = gb.uv.at<cv::Vec2f>(int(y), x);
        const MaterialSample ms = tracer.material(part).evaluate(Vec2f(uv[0], uv[1]));
        const Vec3f c = ms.diffuseColor() + ms.f0();
        for (int k = 0; k < 3; ++k) a[k] = std::clamp(c[k], 0.0f, 1.0f);
      } else {
        g.depth.at<float>(int(y), x) = 0.0f;  // environment (through a window): no surface
        g.normal.at<cv::Vec3f>(int(y), x) = cv::Vec3f(0, 0, 0);
      }
      g.albedo.at<cv::Vec3f>(int(y), x) = a;
    }
  });
  return g;
}

cv::Mat varianceFromHalves(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != CV_32FC3 || b.type() != CV_32FC3 || a.size() != b.size())
    throw std::invalid_argument("ps::varianceFromHalves: two CV_32FC3 images of one size");
  cv::Mat v(a.size(), CV_32FC1);
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      const float d = 0.5f * (luminance(a.at<cv::Vec3f>(y, x)) - luminance(b.at<cv::Vec3f>(y, x)));
      v.at<float>(y, x) = std::isfinite(d) ? d * d : 0.0f;
    }
  cv::Mat blurred;
  cv::blur(v, blurred, cv::Size(3, 3), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  return blurred;
}

}  // namespace ps
