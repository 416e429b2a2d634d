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
  const int W = size.width, H = size.height;
  const size_t N = size_t(W) * H;
  if (N == 0) return cv::Mat(size, CV_32FC3);

  // Demodulate; clean the inputs (NaN / negative -> 0).
  std::vector<cv::Vec3f> demod(N), albedo(N), normal(N);
  std::vector<float> depth(N), gradZ(N, 0.0f), var(N, 0.0f);
  std::vector<uint8_t> surface(N);
  parallelFor(0, H, [&](int64_t y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      const cv::Vec3f c = noisy.at<cv::Vec3f>(int(y), x);
      const cv::Vec3f a = g.albedo.at<cv::Vec3f>(int(y), x);
      const float z = g.depth.at<float>(int(y), x);
      surface[i] = std::isfinite(z) && z > 0.0f;
      depth[i] = surface[i] ? z : 0.0f;
      cv::Vec3f n = g.normal.at<cv::Vec3f>(int(y), x);
      for (int k = 0; k < 3; ++k) n[k] = std::isfinite(n[k]) ? n[k] : 0.0f;
      normal[i] = n;
      for (int k = 0; k < 3; ++k) {
        albedo[i][k] = std::max(std::isfinite(a[k]) ? std::min(a[k], 1.0f) : 1.0f, o.albedoEpsilon);
        demod[i][k] = finitePositive(c[k]) / albedo[i][k];
      }
    }
  });
  // Depth gradient (px^-1), one-sided where a neighbour is background.
  parallelFor(0, H, [&](int64_t y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      if (!surface[i]) continue;
      auto slope = [&](int dx, int dy) {
        // The smaller one-sided difference: a depth edge next to the pixel is not its slope.
        float s = std::numeric_limits<float>::infinity();
        for (int sgn : {-1, 1}) {
          const int xx = x + sgn * dx, yy = int(y) + sgn * dy;
          if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
          const size_t j = size_t(yy) * W + xx;
          if (!surface[j]) continue;
          s = std::min(s, std::abs(depth[j] - depth[i]));
        }
        return std::isfinite(s) ? s : 0.0f;
      };
      const float gx = slope(1, 0), gy = slope(0, 1);
      gradZ[i] = std::sqrt(gx * gx + gy * gy);
    }
  });

  // Initial luminance variance of the demodulated signal.
  if (!g.variance.empty()) {
    parallelFor(0, H, [&](int64_t y) {
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * W + x;
        const float la = luminance(albedo[i]);
        var[i] = finitePositive(g.variance.at<float>(int(y), x)) / (la * la);
      }
    });
  } else {
    // Spatial estimate: variance of the demodulated luminance over the 5x5 neighbours on the
    // same surface (normal within ~25 degrees, depth on the local plane).
    parallelFor(0, H, [&](int64_t y) {
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * W + x;
        if (!surface[i]) continue;
        double s = 0, s2 = 0;
        int n = 0;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const int xx = x + dx, yy = int(y) + dy;
            if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
            const size_t j = size_t(yy) * W + xx;
            if (!surface[j] || normal[i].dot(normal[j]) < 0.9f) continue;
            const float r = std::sqrt(float(dx * dx + dy * dy));
            if (std::abs(depth[j] - depth[i]) > 2.0f * gradZ[i] * r + 1e-2f * depth[i]) continue;
            const double l = luminance(demod[j]);
            s += l;
            s2 += l * l;
            ++n;
          }
        var[i] = n > 1 ? float(std::max(0.0, (s2 - s * s / n) / (n - 1))) : 0.0f;
      }
    });
  }

  std::vector<cv::Vec3f> next(N);
  std::vector<float> nextVar(N), varBlur(N);
  for (int level = 0; level < o.levels; ++level) {
    const int step = 1 << level;
    // 3x3 Gaussian of the variance for the luminance edge-stop (SVGF).
    parallelFor(0, H, [&](int64_t y) {
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * W + x;
        if (!surface[i]) continue;
        float s = 0, ws = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = int(y) + dy;
            if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
            const size_t j = size_t(yy) * W + xx;
            if (!surface[j]) continue;
            const float w = (dx ? 0.5f : 1.0f) * (dy ? 0.5f : 1.0f);
            s += w * var[j];
            ws += w;
          }
        varBlur[i] = s / ws;
      }
    });
    parallelFor(0, H, [&](int64_t y) {
      for (int x = 0; x < W; ++x) {
        const size_t i = size_t(y) * W + x;
        if (!surface[i]) {
          next[i] = demod[i];
          nextVar[i] = var[i];
          continue;
        }
        const float lp = luminance(demod[i]);
        const float lumDenom = o.sigmaLuminance * std::sqrt(varBlur[i]) + 1e-6f;
        const cv::Vec3f np = normal[i];
        const float zp = depth[i];
        cv::Vec3f sum(0, 0, 0);
        float wsum = 0, vsum = 0;
        for (int ky = 0; ky < 5; ++ky) {
          const int yy = int(y) + (ky - 2) * step;
          if (yy < 0 || yy >= H) continue;
          for (int kx = 0; kx < 5; ++kx) {
            const int xx = x + (kx - 2) * step;
            if (xx < 0 || xx >= W) continue;
            const size_t j = size_t(yy) * W + xx;
            if (!surface[j]) continue;
            float w = kB3[kx] * kB3[ky];
            if (j != i) {
              const float nd = std::max(0.0f, np.dot(normal[j]));
              const float wn = o.sigmaNormal > 0 ? std::pow(nd, o.sigmaNormal) : 1.0f;
              const float off = step * std::sqrt(float((kx - 2) * (kx - 2) + (ky - 2) * (ky - 2)));
              const float wz =
                  std::exp(-std::abs(zp - depth[j]) / (o.sigmaDepth * gradZ[i] * off + 1e-3f * zp));
              const float wl = std::exp(-std::abs(lp - luminance(demod[j])) / lumDenom);
              w *= wn * wz * wl;
            }
            sum += w * demod[j];
            wsum += w;
            vsum += w * w * var[j];
          }
        }
        // wsum >= kB3[2]^2 > 0: the center tap always counts.
        next[i] = sum / wsum;
        nextVar[i] = vsum / (wsum * wsum);
      }
    });
    demod.swap(next);
    var.swap(nextVar);
  }

  cv::Mat out(size, CV_32FC3);
  parallelFor(0, H, [&](int64_t y) {
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      cv::Vec3f c;
      for (int k = 0; k < 3; ++k) c[k] = finitePositive(demod[i][k] * albedo[i][k]);
      out.at<cv::Vec3f>(int(y), x) = c;
    }
  });
  return out;
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
