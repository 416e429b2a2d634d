// Finite-difference checks of renderLayerBackward for every input map, the homogeneous roughness
// and metallic, and every UV transform parameter; stress cases (no NaN / Inf).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "photoscene/core.hpp"
#include "photoscene/render.hpp"

namespace ps {
namespace {

// A synthetic part: random uvs, footprints spanning several mip levels, view directions, tangent
// Jacobians (not orthogonal, one mirrored) and an incident-light field with a bright "lamp" bin.
PartGeometry syntheticGeometry(int n, uint64_t seed, int thetaBins = 4, int phiBins = 8) {
  PartGeometry g;
  g.imageSize = cv::Size(16, (n + 15) / 16);
  g.thetaBins = thetaBins;
  g.phiBins = phiBins;
  g.bins = thetaBins * phiBins;
  g.binSolidAngle = 2 * kPi / g.bins;
  for (int i = 0; i < thetaBins; ++i)
    for (int j = 0; j < phiBins; ++j) {
      const float cosT = 1.0f - (i + 0.5f) / thetaBins, phi = 2 * kPi * (j + 0.5f) / phiBins;
      const float sinT = std::sqrt(1 - cosT * cosT);
      g.binDir.emplace_back(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
    }
  Rng rng(seed);
  for (int k = 0; k < n; ++k) {
    g.pixels.emplace_back(k % 16, k / 16);
    PartGeometry::Pixel px;
    px.uv = Vec2f(2 * rng.uniform(), 2 * rng.uniform());
    px.footprint = std::exp2(-6.0f + 5.0f * rng.uniform());  // lod from below 0 to above the top
    const float th = 1.2f * rng.uniform(), ph = 2 * kPi * rng.uniform();
    px.wo = Vec3f(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    const float mirror = (k % 3 == 0) ? -1.0f : 1.0f;
    px.J[0] = 1.0f + 0.3f * rng.uniform();
    px.J[1] = 0.4f * (rng.uniform() - 0.5f);
    px.J[2] = 0.3f * (rng.uniform() - 0.5f);
    px.J[3] = mirror * (0.8f + 0.4f * rng.uniform());
    g.data.push_back(px);
  }
  g.light.resize(static_cast<size_t>(n) * g.bins * 3);
  for (int k = 0; k < n; ++k)
    for (int b = 0; b < g.bins; ++b)
      for (int c = 0; c < 3; ++c) {
        float v = 0.2f + 0.3f * rng.uniform();
        if (b == 2) v += 6.0f;  // a lamp
        g.light[g.lightIndex(k, b, c)] = v;
      }
  return g;
}

cv::Mat randomMap(int n, int channels, float lo, float hi, uint64_t seed) {
  cv::Mat m(n, n, CV_MAKETYPE(CV_32F, channels));
  Rng rng(seed);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n * channels; ++x) m.ptr<float>(y)[x] = lo + (hi - lo) * rng.uniform();
  return m;
}
cv::Mat randomNormalMap(int n, uint64_t seed, float tilt = 0.5f) {
  cv::Mat m(n, n, CV_32FC3);
  Rng rng(seed);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Vec3f v(tilt * (2 * rng.uniform() - 1), tilt * (2 * rng.uniform() - 1), 1.0f);
      v.normalize();
      m.at<cv::Vec3f>(y, x) = cv::Vec3f(v.x(), v.y(), v.z());
    }
  return m;
}

cv::Mat weights(const PartGeometry& g, uint64_t seed) {
  cv::Mat w(g.imageSize, CV_32FC3, cv::Scalar::all(0));
  Rng rng(seed);
  for (const cv::Point& p : g.pixels) w.at<cv::Vec3f>(p) = cv::Vec3f(rng.uniform() - 0.3f, rng.uniform() - 0.3f, rng.uniform() - 0.3f);
  return w;
}

double lossOf(RenderLayerParams p, const cv::Mat& w) {
  renderLayerForward(p);
  double s = 0;
  for (const cv::Point& q : p.geometry->pixels) {
    const cv::Vec3f a = p.image.at<cv::Vec3f>(q), b = w.at<cv::Vec3f>(q);
    s += double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
  }
  return s;
}

struct ErrorStats {
  double maxRel = 0, maxAbsNumeric = 0;
  int checked = 0;
  void add(double analytic, double numeric, double floor) {
    const double e = std::abs(analytic - numeric) / std::max({std::abs(analytic), std::abs(numeric), floor});
    maxRel = std::max(maxRel, e);
    ++checked;
  }
};

// Central differences on every entry of `map` (a clone is perturbed in `p`).
ErrorStats checkMap(RenderLayerParams p, cv::Mat RenderLayerParams::*field, const cv::Mat& analytic, const cv::Mat& w,
                    double h) {
  cv::Mat base = (p.*field).clone();
  std::vector<double> num, ana;
  const int C = base.channels();
  for (int y = 0; y < base.rows; ++y)
    for (int x = 0; x < base.cols * C; ++x) {
      const double a = analytic.ptr<float>(y)[x];
      double best = 0;
      for (double step : {h, h / 4}) {
        cv::Mat plus = base.clone(), minus = base.clone();
        plus.ptr<float>(y)[x] += static_cast<float>(step);
        minus.ptr<float>(y)[x] -= static_cast<float>(step);
        p.*field = plus;
        const double lp = lossOf(p, w);
        p.*field = minus;
        const double lm = lossOf(p, w);
        const double v = (lp - lm) / (2 * step);
        if (step == h || std::abs(v - a) < std::abs(best - a)) best = v;
      }
      num.push_back(best);
      ana.push_back(a);
    }
  double maxNum = 0;
  for (double v : num) maxNum = std::max(maxNum, std::abs(v));
  ErrorStats st;
  st.maxAbsNumeric = maxNum;
  size_t worst = 0;
  for (size_t i = 0; i < num.size(); ++i) {
    const double before = st.maxRel;
    st.add(ana[i], num[i], 0.1 * maxNum);  // entries far below the largest: absolute error
    if (st.maxRel > before) worst = i;
  }
  std::printf("  worst entry %zu: analytic %+.5f numeric %+.5f (max |numeric| %.4f)\n", worst, ana[worst], num[worst], maxNum);
  return st;
}

double numericScalar(RenderLayerParams p, const std::function<void(RenderLayerParams&, float)>& set, float x0,
                     const cv::Mat& w, double h) {
  set(p, static_cast<float>(x0 + h));
  const double lp = lossOf(p, w);
  set(p, static_cast<float>(x0 - h));
  const double lm = lossOf(p, w);
  return (lp - lm) / (2 * h);
}

struct RenderCase {
  PartGeometry geo;
  RenderLayerParams p;
  cv::Mat w;
};

RenderCase makeSetup(bool roughnessMap, float metallic, uint64_t seed) {
  RenderCase s;
  s.geo = syntheticGeometry(96, seed);
  s.p.albedo = randomMap(8, 3, 0.1f, 0.9f, seed + 1);
  s.p.normal = randomNormalMap(8, seed + 2);
  if (roughnessMap) s.p.roughness = randomMap(8, 1, 0.3f, 0.9f, seed + 3);
  s.p.roughnessValue = 0.45f;
  s.p.metallic = metallic;
  s.p.uv.rotation = 0.4f;
  s.p.uv.logScale = 0.2f;
  s.p.uv.offset = Vec2f(0.13f, -0.21f);
  s.w = weights(s.geo, seed + 4);
  return s;
}

TEST(Render_Layer, gradient_maps_match_finite_differences) {
  for (int variant = 0; variant < 3; ++variant) {
    RenderCase s = makeSetup(/*roughnessMap=*/true, variant == 1 ? 0.3f : 0.0f, 100 + variant);
    if (variant == 2) s.p.lobeFilter = 1.0f;  // the roughness map through the lobe filter
    s.p.geometry = &s.geo;
    renderLayerForward(s.p);
    RenderLayerGradients g;
    renderLayerBackward(s.p, s.w, g);
    const ErrorStats a = checkMap(s.p, &RenderLayerParams::albedo, g.albedo, s.w, 1e-3);
    const ErrorStats n = checkMap(s.p, &RenderLayerParams::normal, g.normal, s.w, 1e-3);
    const ErrorStats r = checkMap(s.p, &RenderLayerParams::roughness, g.roughness, s.w, 1e-3);
    std::printf("variant %d: albedo max rel %.2e (%d), normal %.2e (%d), roughness %.2e (%d)\n", variant, a.maxRel,
                a.checked, n.maxRel, n.checked, r.maxRel, r.checked);
    EXPECT_GT(a.maxAbsNumeric, 1e-3);
    EXPECT_GT(n.maxAbsNumeric, 1e-3);
    EXPECT_GT(r.maxAbsNumeric, 1e-3);
    EXPECT_LT(a.maxRel, 2e-2);
    EXPECT_LT(n.maxRel, 2e-2);
    EXPECT_LT(r.maxRel, 2e-2);
  }
}

TEST(Render_Layer, gradient_uv_roughness_metallic_match_finite_differences) {
  for (int variant = 0; variant < 4; ++variant) {
    RenderCase s = makeSetup(/*roughnessMap=*/false, variant == 2 ? 0.25f : 0.0f, 200 + variant);
    s.p.filter = variant != 1;
    if (variant == 3) {  // a glossy lobe through the lobe filter
      s.p.lobeFilter = 1.0f;
      s.p.roughnessValue = 0.2f;
    }
    s.p.geometry = &s.geo;
    renderLayerForward(s.p);
    RenderLayerGradients g;
    renderLayerBackward(s.p, s.w, g);
    struct Item {
      const char* name;
      float analytic;
      std::function<void(RenderLayerParams&, float)> set;
      float x0;
      double h;
    };
    std::vector<Item> items = {
        {"rotation", g.rotation, [](RenderLayerParams& q, float v) { q.uv.rotation = v; }, s.p.uv.rotation, 1e-3},
        {"logScale", g.logScale, [](RenderLayerParams& q, float v) { q.uv.logScale = v; }, s.p.uv.logScale, 1e-3},
        {"offset.x", g.offset.x(), [](RenderLayerParams& q, float v) { q.uv.offset.x() = v; }, s.p.uv.offset.x(), 1e-3},
        {"offset.y", g.offset.y(), [](RenderLayerParams& q, float v) { q.uv.offset.y() = v; }, s.p.uv.offset.y(), 1e-3},
        {"roughness", g.roughnessValue, [](RenderLayerParams& q, float v) { q.roughnessValue = v; }, s.p.roughnessValue, 1e-3},
    };
    if (variant == 2)
      items.push_back({"metallic", g.metallic, [](RenderLayerParams& q, float v) { q.metallic = v; }, s.p.metallic, 1e-3});
    for (const Item& it : items) {
      // the closer of two steps: a bilinear or clamp kink crossed by one step is not crossed by both
      const double n1 = numericScalar(s.p, it.set, it.x0, s.w, it.h);
      const double n2 = numericScalar(s.p, it.set, it.x0, s.w, it.h / 8);
      const double num = std::abs(n1 - it.analytic) < std::abs(n2 - it.analytic) ? n1 : n2;
      const double rel = std::abs(num - it.analytic) / std::max({std::abs(num), std::abs(double(it.analytic)), 1e-2});
      std::printf("variant %d %-9s analytic %+.5f numeric %+.5f rel %.2e\n", variant, it.name, it.analytic, num, rel);
      EXPECT_GT(std::abs(num), 1e-2) << it.name;
      EXPECT_LT(rel, 2e-2) << it.name << " variant " << variant;
    }
  }
}

bool allFinite(const cv::Mat& m) { return m.empty() || cv::checkRange(m); }

TEST(Render_Layer, stress_no_nan_or_inf) {
  PartGeometry geo = syntheticGeometry(64, 7);
  // grazing view, view below the surface, degenerate and infinite footprints, degenerate frames
  geo.data[0].wo = Vec3f(1, 0, 1e-7f).normalized();
  geo.data[1].wo = Vec3f(0, 1, -0.2f).normalized();
  geo.data[2].footprint = 0;
  geo.data[3].footprint = 1e30f;
  geo.data[4].J[0] = geo.data[4].J[1] = geo.data[4].J[2] = geo.data[4].J[3] = 0;
  geo.data[4].frameOk = false;
  geo.data[5].uv = Vec2f(1e6f, -1e6f);
  // grazing light only (all radiance in the last theta row) at some pixels, black light elsewhere
  for (int k = 6; k < 12; ++k)
    for (int b = 0; b < geo.bins; ++b)
      for (int c = 0; c < 3; ++c) geo.light[geo.lightIndex(k, b, c)] = (b / geo.phiBins == geo.thetaBins - 1) ? 50.0f : 0.0f;
  for (int k = 12; k < 14; ++k) std::fill(geo.light.begin() + k * geo.bins * 3, geo.light.begin() + (k + 1) * geo.bins * 3, 0.0f);
  cv::Mat awayNormals(8, 8, CV_32FC3, cv::Scalar(0.9f, 0.0f, 0.1f));  // almost in the plane
  awayNormals.at<cv::Vec3f>(0, 0) = cv::Vec3f(0, 0, -1);                 // pointing into the surface
  awayNormals.at<cv::Vec3f>(1, 1) = cv::Vec3f(0, 0, 0);                  // zero vector
  for (float rough : {0.0f, 1e-4f, 0.5f, 1.0f})
    for (int nm = 0; nm < 3; ++nm)
      for (float albedoValue : {0.0f, 1.0f}) {
        RenderLayerParams p;
        p.geometry = &geo;
        p.albedo = cv::Mat(8, 8, CV_32FC3, cv::Scalar::all(albedoValue));
        p.normal = nm == 0 ? cv::Mat() : nm == 1 ? randomNormalMap(8, 3, 3.0f) : awayNormals;
        p.roughnessValue = rough;
        p.uv.logScale = rough == 0 ? -20.0f : 3.0f;
        renderLayerForward(p);
        ASSERT_TRUE(allFinite(p.image)) << "roughness " << rough << " normals " << nm;
        // black and saturated "photo" gradients
        cv::Mat gimg(geo.imageSize, CV_32FC3, cv::Scalar::all(albedoValue > 0 ? 1e3 : -1.0));
        RenderLayerGradients gr;
        renderLayerBackward(p, gimg, gr);
        EXPECT_TRUE(allFinite(gr.albedo) && allFinite(gr.normal));
        EXPECT_TRUE(std::isfinite(gr.rotation) && std::isfinite(gr.logScale) && gr.offset.allFinite() &&
                    std::isfinite(gr.roughnessValue));
      }
  // one pixel
  PartGeometry one = syntheticGeometry(1, 9);
  RenderLayerParams p;
  p.geometry = &one;
  p.albedo = randomMap(4, 3, 0, 1, 3);
  renderLayerForward(p);
  EXPECT_TRUE(allFinite(p.image));
  EXPECT_GT(cv::norm(p.image), 0.0);
}

TEST(Render_Layer, lambert_under_uniform_light_is_albedo_times_radiance) {
  // A white furnace: uniform radiance L over the hemisphere, Lambertian (specular 0) -> I = A L,
  // whatever the view, the normal map (while n stays in the hemisphere) and the UV transform.
  PartGeometry geo = syntheticGeometry(32, 11, 8, 16);
  std::fill(geo.light.begin(), geo.light.end(), 2.0f);
  RenderLayerParams p;
  p.geometry = &geo;
  p.albedo = cv::Mat(4, 4, CV_32FC3, cv::Scalar(0.2f, 0.5f, 0.8f));
  p.specular = 0;
  p.uv.rotation = 1.0f;
  renderLayerForward(p);
  for (const Vec3f& v : gatherPixels(geo, p.image)) {
    EXPECT_NEAR(v.x(), 0.4f, 0.4f * 0.01f);
    EXPECT_NEAR(v.z(), 1.6f, 1.6f * 0.01f);
  }
}

TEST(Render_Layer, glossy_under_uniform_light_reflects_its_directional_albedo) {
  // A white furnace for the specular term: a mirror-like metal (F0 = 1, so F = 1) under uniform
  // radiance L reflects L E(wo), E(wo) = the mean of G1(wi) over GGX's visible normals (<= 1,
  // close to 1 for a narrow lobe). The layer sums the lobe over a few directions per bin: without
  // the lobe filter a lobe narrower than their spacing falls between them (I near 0) or on one of
  // them (I many times L): the grid's points then show as bright blobs on a glossy part.
  PartGeometry geo = syntheticGeometry(96, 13, 8, 16);
  std::fill(geo.light.begin(), geo.light.end(), 1.0f);
  for (PartGeometry::Pixel& px : geo.data) {  // views up to 60 degrees from the normal
    const Vec3f& w = px.wo;
    px.wo = Vec3f(w.x(), w.y(), std::max(w.z(), 0.5f)).normalized();
  }
  for (float rough : {0.03f, 0.1f, 0.2f, 0.4f}) {
    // the reference per pixel, once per roughness
    const float alpha = ggxAlpha(rough);
    std::vector<double> albedo(geo.size(), 0.0);
    for (int k = 0; k < geo.size(); ++k) {
      const Vec3f& wo = geo.data[k].wo;
      Rng rng(17 + k);
      const int n = 4000;
      for (int s = 0; s < n; ++s) {
        const Vec3f h = sampleGgxVisibleNormal(wo, alpha, rng.uniform(), rng.uniform());
        const Vec3f wi = 2 * wo.dot(h) * h - wo;
        if (wi.z() > 0) albedo[k] += smithG1(wi, alpha) / n;
      }
    }
    for (int sub : {1, 2})
      for (bool filtered : {true, false}) {
        RenderLayerParams p;
        p.geometry = &geo;
        p.albedo = cv::Mat(4, 4, CV_32FC3, cv::Scalar::all(1.0f));
        p.metallic = 1.0f;
        p.roughnessValue = rough;
        p.specularSub = sub;
        p.lobeFilter = filtered ? 1.0f : 0.0f;
        renderLayerForward(p);
        double worst = 0, meanRatio = 0;
        for (int k = 0; k < geo.size(); ++k) {
          const double e = albedo[k];
          const float I = p.image.at<cv::Vec3f>(geo.pixels[k])[1];
          worst = std::max(worst, std::abs(I - e) / e);
          meanRatio += I / e / geo.size();
        }
        std::printf("sub %d roughness %.2f lobe filter %.2f: I / (L E) %.3f on average, worst relative error %.3f\n", sub,
                    rough, p.lobeFilter, meanRatio, worst);
        if (filtered) {
          // within 25 % everywhere; on average a little low (the widened lobe's own energy loss)
          EXPECT_LT(worst, 0.25) << "sub " << sub << " roughness " << rough;
          EXPECT_GT(meanRatio, 0.85) << "sub " << sub << " roughness " << rough;
          EXPECT_LT(meanRatio, 1.02) << "sub " << sub << " roughness " << rough;
        } else if (rough <= 0.1f) {
          EXPECT_GT(worst, 2.0) << "without the filter the narrow lobe is missed or hit";
        }
      }
  }
}

}  // namespace
}  // namespace ps
