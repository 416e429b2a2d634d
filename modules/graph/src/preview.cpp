// Lit previews of material maps (core/shading.hpp's Lambert + GGX, separable Smith, Schlick
// Fresnel: the BRDF the path tracer and the render layer evaluate).
#include "photoscene/graph/preview.hpp"

#include "photoscene/core.hpp"
#include "photoscene/core/shading.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace ps {
namespace {

cv::Vec3f sample3(const cv::Mat& m, float u, float v) {
  const int n = m.cols;
  const float x = (u - std::floor(u)) * n - 0.5f, y = (1.f - (v - std::floor(v))) * n - 0.5f;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  auto at = [&](int xx, int yy) {
    xx = wrapIndex(xx, n), yy = wrapIndex(yy, m.rows);
    if (m.channels() == 1) return cv::Vec3f::all(m.at<float>(yy, xx));
    return m.at<cv::Vec3f>(yy, xx);
  };
  return (at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx) * (1 - fy) +
         (at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx) * fy;
}

/// A mip pyramid of a periodic map (exact 2x box downsampling) with trilinear lookup, so the
/// preview shows each texel footprint's mean instead of aliasing (moire) on fine patterns.
struct Mips {
  std::vector<cv::Mat> level;
  explicit Mips(const cv::Mat& m) {
    if (m.empty()) return;
    level.push_back(m);
    while (level.back().cols > 1 && level.back().rows > 1) {
      cv::Mat d;
      cv::resize(level.back(), d, cv::Size(level.back().cols / 2, level.back().rows / 2), 0, 0, cv::INTER_AREA);
      level.push_back(d);
    }
  }
  /// footprint: size of the sample's footprint in level-0 texels.
  cv::Vec3f sample(float u, float v, float footprint) const {
    const float lod = std::clamp(std::log2(std::max(footprint, 1e-6f)), 0.f, float(level.size() - 1));
    const int l0 = int(lod);
    const float t = lod - l0;
    const cv::Vec3f a = sample3(level[l0], u, v);
    if (t <= 0 || l0 + 1 >= int(level.size())) return a;
    return a * (1 - t) + sample3(level[l0 + 1], u, v) * t;
  }
};

cv::Vec3f normalized(cv::Vec3f v) {
  const float l = std::sqrt(v.dot(v));
  return l > 1e-12f ? v / l : cv::Vec3f(0, 0, 1);
}

}  // namespace

cv::Mat renderMaterialPreview(const MaterialMaps& maps, const PreviewOptions& o) {
  checkImage(maps.albedo, CV_32FC3, "preview albedo");
  checkImage(maps.normal, CV_32FC3, "preview normal");
  checkImage(maps.roughness, CV_32FC1, "preview roughness");
  const int S = o.size;
  cv::Mat out(S, S, CV_32FC3);
  const cv::Vec3f Ldir = normalized({-0.55f, 0.6f, 0.75f});
  const cv::Vec3f V(0, 0, 1);
  const float Li = 3.2f, ambient = 0.22f;
  const float kPi = 3.14159265f;
  const Mips mAlb(maps.albedo), mNrm(maps.normal), mRough(maps.roughness), mMetal(maps.metallic);
  const int n = maps.albedo.cols;
  // surface point at screen position (px, py) in [-1, 1]^2: false outside the sphere
  auto surface = [&](float px, float py, cv::Vec3f& N, cv::Vec3f& T, cv::Vec3f& B, float& u, float& v) {
    if (o.shape == PreviewShape::Sphere) {
      const float r2 = px * px + py * py;
      if (r2 >= 0.98f) return false;
      N = normalized(cv::Vec3f(px, py, std::sqrt(1 - r2)) / std::sqrt(0.98f));
      const float phi = std::atan2(N[0], N[2]);
      u = (phi / kPi * 0.5f + 0.5f) * o.uvRepeat * 2.f;
      v = (std::asin(std::clamp(N[1], -1.f, 1.f)) / kPi + 0.5f) * o.uvRepeat;
      T = normalized({std::cos(phi), 0, -std::sin(phi)});
      B = normalized(N.cross(T));
    } else {
      N = {0, 0, 1};
      T = {1, 0, 0};
      B = {0, 1, 0};
      u = (px * 0.5f + 0.5f) * o.uvRepeat;
      v = (py * 0.5f + 0.5f) * o.uvRepeat;
    }
    return true;
  };
  // 3 x 3 samples per pixel, each with a mip lookup of its own footprint (a third of a pixel)
  constexpr int kSub = 3;
  const float h = 2.f / S / kSub;  // sample spacing in screen units
  parallelFor(0, S, [&](int64_t yy) {
    const int y = int(yy);
    for (int x = 0; x < S; ++x) {
      cv::Vec3f acc(0, 0, 0);
      for (int sj = 0; sj < kSub; ++sj)
        for (int si = 0; si < kSub; ++si) {
          const float px = (x + (si + 0.5f) / kSub) / S * 2 - 1, py = 1 - (y + (sj + 0.5f) / kSub) / S * 2;
          cv::Vec3f N, T, B;
          float u, v;
          if (!surface(px, py, N, T, B, u, v)) {
            acc += o.background;
            continue;
          }
          // footprint from the uv change to the neighbouring samples (u wraps on the sphere)
          float foot = 0;
          for (int d = 0; d < 2; ++d) {
            cv::Vec3f N2, T2, B2;
            float u2, v2;
            if (!surface(px + (d == 0 ? h : 0), py - (d == 1 ? h : 0), N2, T2, B2, u2, v2) &&
                !surface(px - (d == 0 ? h : 0), py + (d == 1 ? h : 0), N2, T2, B2, u2, v2))
              continue;
            float du = std::abs(u2 - u);
            const float period = o.uvRepeat * 2.f;
            if (o.shape == PreviewShape::Sphere && du > 0.5f * period) du = period - du;
            foot = std::max(foot, std::max(du, std::abs(v2 - v)) * n);
          }
          const cv::Vec3f albedo = mAlb.sample(u, v, foot);
          const cv::Vec3f tn = mNrm.sample(u, v, foot);
          const float rough = std::clamp(mRough.sample(u, v, foot)[0], 0.02f, 1.f);
          const float metal = maps.metallic.empty() ? 0.f : std::clamp(mMetal.sample(u, v, foot)[0], 0.f, 1.f);
          const cv::Vec3f nrm = normalized(tn[0] * T + tn[1] * B + tn[2] * N);
          const float nl = std::max(0.f, nrm.dot(Ldir)), nv = std::max(1e-4f, nrm.dot(V));
          const cv::Vec3f hv = normalized(Ldir + V);
          const float nh = std::max(0.f, nrm.dot(hv)), vh = std::max(0.f, V.dot(hv));
          // the path tracer's and the render layer's BRDF (core/shading.hpp): Lambert + GGX D
          // x separable Smith G1 G1 / (4 nl nv) = D G1(nl) K(nv) / nl, Schlick F
          const float a = rough * rough, a2 = a * a;
          const float D = shading::ggxD(nh, a2);
          const float GK = shading::smithG1(nl, a2) * shading::specularK(nv, a).value;
          const cv::Vec3f F0 = cv::Vec3f::all(0.04f) * (1 - metal) + albedo * metal;
          const float fw = shading::schlickWeight(vh);
          const cv::Vec3f F = F0 + (cv::Vec3f::all(1) - F0) * fw;
          const cv::Vec3f diffuse = albedo * (1 - metal) * shading::kLambert;
          cv::Vec3f c = diffuse * (Li * nl) + F * (D * GK * Li);
          const float sky = 0.5f + 0.5f * nrm[1];
          c += (albedo * (1 - metal) + F0 * 0.5f) * (ambient * (0.6f + 0.4f * sky));
          acc += c;
        }
      out.at<cv::Vec3f>(y, x) = acc / float(kSub * kSub);
    }
  }, 8);
  return out;
}

}  // namespace ps
