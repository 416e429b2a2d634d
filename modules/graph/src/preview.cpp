// Lit previews of material maps (Lambert + GGX, Smith height-correlated, Schlick Fresnel).
#include "photoscene/graph/preview.hpp"

#include "photoscene/core.hpp"

#include <cmath>

namespace ps {
namespace {

cv::Vec3f sample3(const cv::Mat& m, float u, float v) {
  const int n = m.cols;
  const float x = (u - std::floor(u)) * n - 0.5f, y = (1.f - (v - std::floor(v))) * n - 0.5f;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = x - x0, fy = y - y0;
  auto at = [&](int xx, int yy) {
    xx = ((xx % n) + n) % n, yy = ((yy % m.rows) + m.rows) % m.rows;
    if (m.channels() == 1) return cv::Vec3f::all(m.at<float>(yy, xx));
    return m.at<cv::Vec3f>(yy, xx);
  };
  return (at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx) * (1 - fy) +
         (at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx) * fy;
}

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
  parallelFor(0, S, [&](int64_t yy) {
    const int y = int(yy);
    for (int x = 0; x < S; ++x) {
      const float px = (x + 0.5f) / S * 2 - 1, py = 1 - (y + 0.5f) / S * 2;
      cv::Vec3f N, T, B;
      float u, v;
      if (o.shape == PreviewShape::Sphere) {
        const float r2 = px * px + py * py;
        if (r2 >= 0.98f) {
          out.at<cv::Vec3f>(y, x) = o.background;
          continue;
        }
        N = cv::Vec3f(px, py, std::sqrt(1 - r2)) / std::sqrt(0.98f);
        N = normalized(N);
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
      const cv::Vec3f albedo = sample3(maps.albedo, u, v);
      const cv::Vec3f tn = sample3(maps.normal, u, v);
      const float rough = std::clamp(sample3(maps.roughness, u, v)[0], 0.02f, 1.f);
      const float metal = maps.metallic.empty() ? 0.f : std::clamp(sample3(maps.metallic, u, v)[0], 0.f, 1.f);
      const cv::Vec3f n = normalized(tn[0] * T + tn[1] * B + tn[2] * N);
      const float nl = std::max(0.f, n.dot(Ldir)), nv = std::max(1e-4f, n.dot(V));
      const cv::Vec3f h = normalized(Ldir + V);
      const float nh = std::max(0.f, n.dot(h)), vh = std::max(0.f, V.dot(h));
      const float a = rough * rough, a2 = a * a;
      const float dd = nh * nh * (a2 - 1) + 1;
      const float D = a2 / (kPi * dd * dd + 1e-12f);
      const float Vis = 0.5f / (nl * std::sqrt(nv * nv * (1 - a2) + a2) +
                                nv * std::sqrt(nl * nl * (1 - a2) + a2) + 1e-6f);
      const cv::Vec3f F0 = cv::Vec3f::all(0.04f) * (1 - metal) + albedo * metal;
      const float fw = std::pow(1 - vh, 5.f);
      const cv::Vec3f F = F0 + (cv::Vec3f::all(1) - F0) * fw;
      const cv::Vec3f diffuse = albedo * (1 - metal) / kPi;
      cv::Vec3f c = (diffuse + F * (D * Vis)) * (Li * nl);
      const float sky = 0.5f + 0.5f * n[1];
      c += (albedo * (1 - metal) + F0 * 0.5f) * (ambient * (0.6f + 0.4f * sky));
      out.at<cv::Vec3f>(y, x) = c;
    }
  }, 8);
  return out;
}

}  // namespace ps
