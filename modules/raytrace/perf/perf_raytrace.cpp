// Benchmarks of the raytrace module on the blender-room ground-truth twin (skipped when the
// shared data is absent):
//   BM_BuildBvh            Embree build over the 12.6k-triangle room
//   BM_GBuffer             G-buffers at 640x480 (center rays + 2x2 coverage rays)
//   BM_Render/<spp>        path tracing view 0 at 320x240; counters: rays/s, RMSE against a
//                          high-spp reference of this renderer (made once, 1024 spp at 160x120 ->
//                          compared at 160x120 after area-averaging), time
//   BM_RenderPerLight/<0|1> the per-light images of view 0 at 320x240, 16 spp: one render per
//                          light (0) against one trace for all (1, renderPerLight)
//   BM_IncidentLightGrid   grid at stride 16 on 320x240 (8x16 bins, 4 samples per bin)
//   BM_Sampler/<0|1>       256 samples of one pixel, a 2D and a 1D dimension each: the sampler
//                          (1) against the scrambles of sobol::dim0 / dim1 written out (0, the
//                          same values with the bit reversals that cancel)
//   BM_IncidentLightRepresentation  measurement: shading error of the 8x16 grid and of SH fits
//                          against a BSDF-importance-sampled reference, per roughness
// Cycles is not run from here (no Blender scene export from a twin yet); the case records
// Cycles' own times (gt/README: 164 s for view0 at 256 spp, 483 s for lambert_view0 at 1024 spp,
// 640x480, 2 threads).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/raytrace/sampler.hpp"
#include "photoscene/scene.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;

fs::path twinDir(const char* name = "twin") {
  return fs::path(PS_SHARED_DATA_DIR) / "examples" / "blender-room" / "gt" / name;
}

struct Loaded {
  std::unique_ptr<Twin> twin;
  std::unique_ptr<PathTracer> tracer;
};

Loaded& loaded() {
  static Loaded l;
  static std::once_flag once;
  std::call_once(once, [] {
    if (!fs::exists(twinDir() / "scene.json")) return;
    setLogLevel(LogLevel::Warn);
    l.twin = std::make_unique<Twin>(loadTwin(twinDir()));
    l.tracer = std::make_unique<PathTracer>(l.twin->scene, l.twin->materials);
  });
  return l;
}

const cv::Mat& reference160() {
  static cv::Mat ref;
  static std::once_flag once;
  std::call_once(once, [] {
    Loaded& l = loaded();
    RenderOptions o;
    o.spp = 1024;
    o.seed = 999;
    ref = l.tracer->render(l.twin->scene.views[0].camera.resized(160, 120), o);
  });
  return ref;
}

double rmse(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d = a - b;
  d = d.mul(d);
  const cv::Scalar m = cv::mean(d);
  return std::sqrt((m[0] + m[1] + m[2]) / 3);
}

void BM_BuildBvh(benchmark::State& state) {
  Loaded& l = loaded();
  if (!l.twin) return state.SkipWithError("blender-room case absent");
  double build = 0;
  for (auto _ : state) {
    RayAccel accel(l.twin->scene.mesh, l.twin->scene.lights.area);
    build = accel.buildSeconds();
    benchmark::DoNotOptimize(&accel);
  }
  state.counters["triangles"] = static_cast<double>(l.twin->scene.mesh.numTriangles());
  state.counters["build_ms"] = build * 1e3;
}
BENCHMARK(BM_BuildBvh)->Unit(benchmark::kMillisecond);

void BM_GBuffer(benchmark::State& state) {
  Loaded& l = loaded();
  if (!l.twin) return state.SkipWithError("blender-room case absent");
  const Camera cam = l.twin->scene.views[0].camera;
  for (auto _ : state) {
    GBuffer gb = renderGBuffer(*l.tracer, cam, {2});
    benchmark::DoNotOptimize(gb.partId.data);
  }
  state.counters["pixels"] = cam.width() * cam.height();
}
BENCHMARK(BM_GBuffer)->Unit(benchmark::kMillisecond);

void BM_Render(benchmark::State& state) {
  Loaded& l = loaded();
  if (!l.twin) return state.SkipWithError("blender-room case absent");
  const int spp = static_cast<int>(state.range(0));
  const Camera cam = l.twin->scene.views[0].camera.resized(320, 240);
  RenderOptions o;
  o.spp = spp;
  RenderStats st;
  cv::Mat img;
  for (auto _ : state) img = l.tracer->render(cam, o, &st);
  cv::Mat small;
  cv::resize(img, small, cv::Size(160, 120), 0, 0, cv::INTER_AREA);
  state.counters["Mrays_per_s"] = st.raysPerSecond() * 1e-6;
  state.counters["rays_per_sample"] = static_cast<double>(st.rays) / st.samples;
  state.counters["rmse_vs_1024spp"] = rmse(small, reference160());
  state.counters["seconds"] = st.seconds;
}
BENCHMARK(BM_Render)->Arg(4)->Arg(16)->Arg(64)->Unit(benchmark::kMillisecond)->Iterations(1);

// The lighting least squares' images of view 0 at 320x240: one trace for every light
// (renderPerLight, arg 1) against one render per light (arg 0, what it did before).
void BM_RenderPerLight(benchmark::State& state) {
  Loaded& l = loaded();
  if (!l.twin) return state.SkipWithError("blender-room case absent");
  const Camera cam = l.twin->scene.views[0].camera.resized(320, 240);
  RenderOptions o;
  o.spp = 16;
  const int n = static_cast<int>(l.twin->scene.lights.size());
  RenderStats total;
  for (auto _ : state) {
    total = {};
    if (state.range(0) == 1) {
      benchmark::DoNotOptimize(l.tracer->renderPerLight(cam, o, &total).data());
    } else {
      for (int i = 0; i < n; ++i) {
        o.lights = LightSelection::one(i);
        RenderStats st;
        benchmark::DoNotOptimize(l.tracer->render(cam, o, &st).data);
        total.seconds += st.seconds;
        total.rays += st.rays;
      }
    }
  }
  state.counters["lights"] = n;
  state.counters["Mrays"] = total.rays * 1e-6;
  state.counters["seconds"] = total.seconds;
}
BENCHMARK(BM_RenderPerLight)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_IncidentLightGrid(benchmark::State& state) {
  Loaded& l = loaded();
  if (!l.twin) return state.SkipWithError("blender-room case absent");
  const Camera cam = l.twin->scene.views[0].camera.resized(320, 240);
  const GBuffer gb = renderGBuffer(*l.tracer, cam, {1});
  IncidentLightOptions o;
  o.stride = 16;
  for (auto _ : state) {
    IncidentLightGrid g = computeIncidentLight(*l.tracer, gb, cam, o);
    benchmark::DoNotOptimize(g.radiance.data());
  }
  state.counters["points"] = ((320 + 15) / 16) * ((240 + 15) / 16);
}
// The sampler's dimensions as written out before the reversal shortcuts (same values; the
// hashes here stand in for the sampler's private per-pixel key).
float referenceGet1D(uint64_t h, uint32_t index) {
  const uint32_t i = sobol::nestedUniformScramble(index, static_cast<uint32_t>(h));
  return sobol::toUnit(
      sobol::nestedUniformScramble(sobol::dim0(i), static_cast<uint32_t>(h >> 32)));
}
Vec2f referenceGet2D(uint64_t h, uint32_t index) {
  const uint32_t i = sobol::nestedUniformScramble(index, static_cast<uint32_t>(h));
  const uint64_t h2 = mix64(h);
  return Vec2f(
      sobol::toUnit(sobol::nestedUniformScramble(sobol::dim0(i), static_cast<uint32_t>(h2))),
      sobol::toUnit(sobol::nestedUniformScramble(sobol::dim1(i), static_cast<uint32_t>(h2 >> 32))));
}

void BM_Sampler(benchmark::State& state) {
  const bool sampler = state.range(0) != 0;
  uint64_t pixel = 0;
  for (auto _ : state) {
    SobolSampler s(7, ++pixel);
    const uint64_t h1 = mix64(pixel), h2 = mix64(h1);
    float sum = 0;
    for (uint32_t i = 0; i < 256; ++i) {
      s.startSample(i);
      const Vec2f p = sampler ? s.get2D(3) : referenceGet2D(h2, i);
      sum += p.x() + p.y() + (sampler ? s.get1D(4) : referenceGet1D(h1, i));
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * 256);
}
BENCHMARK(BM_Sampler)->Arg(0)->Arg(1);

BENCHMARK(BM_IncidentLightGrid)->Unit(benchmark::kMillisecond)->Iterations(1);

// Shading error of representations of the incident light, per roughness: the 8 x 16 grid (as
// the paper), SH with 3 and 5 bands fitted to the same grid, against a reference made by BSDF
// importance sampling of path-traced incident radiance (16384 samples per point; the grid gets 64
// path samples per bin).
void BM_IncidentLightRepresentation(benchmark::State& state) {
  Loaded& l = loaded();
  if (!l.twin) return state.SkipWithError("blender-room case absent");
  const float roughness = static_cast<float>(state.range(0)) / 100.0f;
  const Camera cam = l.twin->scene.views[0].camera.resized(160, 120);
  const GBuffer gb = renderGBuffer(*l.tracer, cam, {1});
  IncidentLightOptions o;
  o.stride = 20;
  o.samplesPerBin = 64;
  double errGrid = 0, errSh3 = 0, errSh5 = 0, refSum = 0;
  for (auto _ : state) {
    const IncidentLightGrid g = computeIncidentLight(*l.tracer, gb, cam, o);
    const MicrofacetBsdf bsdf(Vec3f::Constant(0.5f), Vec3f::Constant(0.04f), roughness);
    errGrid = errSh3 = errSh5 = refSum = 0;
    Rng rng(7);
    for (int gy = 0; gy < g.height; ++gy)
      for (int gx = 0; gx < g.width; ++gx) {
        const size_t k = static_cast<size_t>(gy) * g.width + gx;
        if (!g.valid[k]) continue;
        // view direction: towards the camera, in the grid point's frame
        const Vec3f toCam = (cam.position().cast<float>() - g.position[k]).normalized();
        Vec3f wo(toCam.dot(g.frameT[k]), toCam.dot(g.frameB[k]), toCam.dot(g.frameN[k]));
        if (wo.z() <= 0.05f) continue;
        wo.normalize();
        Vec3f ref = Vec3f::Zero();
        const int n = 16384;
        const Vec3f org = g.position[k] + g.frameN[k] * 1e-4f;
        for (int s = 0; s < n; ++s) {
          BsdfSample bs;
          if (!bsdf.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &bs)) continue;
          const Vec3f dir =
              bs.wi.x() * g.frameT[k] + bs.wi.y() * g.frameB[k] + bs.wi.z() * g.frameN[k];
          const Vec3f L = l.tracer->radiance(org, dir, o.render, rng);
          ref += L.cwiseProduct(bs.f) * (bs.wi.z() / bs.pdf);
        }
        ref /= n;
        const Vec3f grid = g.shade(gx, gy, bsdf, wo, 4);
        auto shShade = [&](int bands) {
          const ShRadiance sh = projectToSh(g, gx, gy, bands);
          Vec3f s = Vec3f::Zero();
          const int nt = 64, np = 128;
          for (int i = 0; i < nt; ++i)
            for (int j = 0; j < np; ++j) {
              const float c = 1 - (i + 0.5f) / nt, ph = 2 * kPi * (j + 0.5f) / np;
              const float st = std::sqrt(1 - c * c);
              const Vec3f wi(st * std::cos(ph), st * std::sin(ph), c);
              s += sh.eval(wi).cwiseProduct(bsdf.eval(wo, wi)) * c;
            }
          return Vec3f(s * (2 * kPi / (nt * np)));
        };
        errGrid += std::abs(grid.y() - ref.y());
        errSh3 += std::abs(shShade(3).y() - ref.y());
        errSh5 += std::abs(shShade(5).y() - ref.y());
        refSum += ref.y();
      }
  }
  state.counters["rel_err_grid8x16"] = errGrid / refSum;
  state.counters["rel_err_sh3"] = errSh3 / refSum;
  state.counters["rel_err_sh5"] = errSh5 / refSum;
}
BENCHMARK(BM_IncidentLightRepresentation)
    ->Arg(100)
    ->Arg(50)
    ->Arg(25)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace ps
