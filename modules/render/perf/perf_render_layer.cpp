// Render layer timing on a synthetic 20k-pixel part (8 x 16 light bins, 256 x 256 maps), on one
// thread (threads:1) and on all (threads:0).
#include <benchmark/benchmark.h>

#include <cmath>

#include "photoscene/core.hpp"
#include "photoscene/render.hpp"

namespace ps {
namespace {

PartGeometry makeGeometry(int n) {
  PartGeometry g;
  const int w = 160;
  g.imageSize = cv::Size(w, (n + w - 1) / w);
  g.thetaBins = 8;
  g.phiBins = 16;
  g.bins = 128;
  g.binSolidAngle = 2 * kPi / g.bins;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 16; ++j) {
      const float c = 1.0f - (i + 0.5f) / 8, phi = 2 * kPi * (j + 0.5f) / 16, s = std::sqrt(1 - c * c);
      g.binDir.emplace_back(s * std::cos(phi), s * std::sin(phi), c);
    }
  Rng rng(1);
  g.light.resize(static_cast<size_t>(n) * 128 * 3);
  for (int k = 0; k < n; ++k) {
    g.pixels.emplace_back(k % w, k / w);
    PartGeometry::Pixel px;
    px.uv = Vec2f((k % w) / 40.0f, (k / w) / 40.0f);
    px.footprint = 1 / 40.0f;
    px.wo = Vec3f(0.3f, 0.2f, 0.93f).normalized();
    g.data.push_back(px);
    for (int b = 0; b < 128; ++b)
      for (int c = 0; c < 3; ++c) g.light[g.lightIndex(k, b, c)] = 0.2f + (b == 5 ? 8.0f : 0.1f * rng.uniform());
  }
  return g;
}

struct Fixture {
  PartGeometry geo = makeGeometry(20000);
  RenderLayerParams p;
  Fixture() {
    p.geometry = &geo;
    p.albedo = cv::Mat(256, 256, CV_32FC3, cv::Scalar(0.5f, 0.4f, 0.3f));
    cv::randu(p.albedo, 0.1f, 0.9f);
    p.normal = cv::Mat(256, 256, CV_32FC3, cv::Scalar(0.1f, -0.1f, 0.99f));
    p.roughnessValue = 0.5f;
  }
};

void BM_RenderLayerForward(benchmark::State& st) {
  Fixture f;
  f.p.specularSub = static_cast<int>(st.range(0));
  f.p.specular = st.range(1) ? 0.5f : 0.0f;
  const ThreadLimit limit(static_cast<int>(st.range(2)));
  for (auto _ : st) {
    renderLayerForward(f.p);
    benchmark::DoNotOptimize(f.p.image.data);
  }
  st.counters["pixels"] = f.geo.size();
}
BENCHMARK(BM_RenderLayerForward)->ArgsProduct({{1, 2}, {0, 1}, {1, 0}})->ArgNames({"sub", "specular", "threads"})->Unit(benchmark::kMillisecond);

void BM_RenderLayerForwardBackward(benchmark::State& st) {
  Fixture f;
  f.p.specularSub = static_cast<int>(st.range(0));
  f.p.specular = st.range(1) ? 0.5f : 0.0f;
  const ThreadLimit limit(static_cast<int>(st.range(2)));
  cv::Mat g(f.geo.imageSize, CV_32FC3, cv::Scalar::all(1e-3));
  RenderLayerGradients gr;
  for (auto _ : st) {
    renderLayerForward(f.p);
    renderLayerBackward(f.p, g, gr);
    benchmark::DoNotOptimize(gr.rotation);
  }
  st.counters["pixels"] = f.geo.size();
}
BENCHMARK(BM_RenderLayerForwardBackward)->ArgsProduct({{1, 2}, {0, 1}, {1, 0}})->ArgNames({"sub", "specular", "threads"})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ps
