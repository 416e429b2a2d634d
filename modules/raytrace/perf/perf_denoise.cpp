// BM_Denoise/<width>: ps::denoise (5 a-trous levels, variance estimated from the image) on a
// synthetic 4:3 frame of <width> x <width> * 3 / 4 pixels: two walls (normal and depth edges),
// a checker albedo, noise proportional to the signal. Counter ms_per_MP: wall milliseconds
// per megapixel.
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include "photoscene/raytrace/denoise.hpp"

namespace ps {
namespace {

void BM_Denoise(benchmark::State& state) {
  const int w = int(state.range(0)), h = w * 3 / 4;
  DenoiseGuides g;
  g.albedo.create(h, w, CV_32FC3);
  g.normal.create(h, w, CV_32FC3);
  g.depth.create(h, w, CV_32FC1);
  cv::Mat clean(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool left = x < w / 2;
      g.albedo.at<cv::Vec3f>(y, x) =
          ((x / 8 + y / 8) % 2) ? cv::Vec3f(0.1f, 0.2f, 0.2f) : cv::Vec3f(0.8f, 0.7f, 0.6f);
      g.normal.at<cv::Vec3f>(y, x) = left ? cv::Vec3f(0, 0, 1) : cv::Vec3f(1, 0, 0);
      g.depth.at<float>(y, x) = left ? 2.0f : 2.0f + 2.0f * x / w;
      clean.at<cv::Vec3f>(y, x) = g.albedo.at<cv::Vec3f>(y, x) * (left ? 1.0f : 0.3f);
    }
  cv::Mat n(h, w, CV_32FC3);
  cv::RNG(1).fill(n, cv::RNG::NORMAL, 0.0, 0.3);
  cv::Mat noisy = cv::max(clean.mul(cv::Scalar::all(1.0) + n), 0.0);
  for (auto _ : state) {
    cv::Mat out = denoise(g, noisy);
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["ms_per_MP"] =
      benchmark::Counter(1e-3 * state.iterations() * (double(w) * h * 1e-6),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Denoise)->Arg(320)->Arg(640)->Arg(1280)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace ps
