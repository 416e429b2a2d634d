// Timings of the texture loss (forward, forward + backward) and the kNN key on a part of about
// 20k pixels in a 320 x 240 view (the per-part fit's working point), and of the target set-up.
#include "photoscene/core.hpp"
#include "photoscene/features.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

namespace {

cv::Mat texture(uint64_t seed, double blur) {
  ps::Rng rng(seed);
  cv::Mat n(240, 320, CV_32FC3);
  n.forEach<cv::Vec3f>([&](cv::Vec3f& p, const int* pos) {
    ps::Rng r = rng.split(pos[0] * 320 + pos[1]);
    p = cv::Vec3f(r.uniform(), r.uniform(), r.uniform());
  });
  cv::GaussianBlur(n, n, cv::Size(0, 0), blur);
  return n * 0.5 + 0.2;
}

cv::Mat partMask() {  // a disk of radius 80: 20,100 pixels
  cv::Mat m = cv::Mat::zeros(240, 320, CV_8UC1);
  cv::circle(m, {160, 120}, 80, cv::Scalar(255), cv::FILLED);
  return m;
}

void threads(benchmark::State& state, std::unique_ptr<ps::ThreadLimit>& limit) {
  limit = std::make_unique<ps::ThreadLimit>(static_cast<int>(state.range(0)));
}

void BM_TextureLossForward(benchmark::State& state) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  ps::TextureLossTarget target(texture(1, 1.0), partMask());
  ps::TextureLossParams p;
  p.target = &target;
  p.render = texture(2, 2.0);
  for (auto _ : state) benchmark::DoNotOptimize(ps::textureLossForward(p));
}
BENCHMARK(BM_TextureLossForward)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// Forward + backward of the loss with `options` on the benchmark's photo and render.
void lossForwardBackward(benchmark::State& state, const ps::TextureLossOptions& options) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  ps::TextureLossTarget target(texture(1, 1.0), partMask(), options);
  ps::TextureLossParams p;
  p.target = &target;
  p.render = texture(2, 2.0);
  cv::Mat grad;
  for (auto _ : state) {
    ps::textureLossForward(p);
    ps::textureLossBackward(p, 1.0f, grad);
    benchmark::DoNotOptimize(grad.data);
  }
}

void BM_TextureLossForwardBackward(benchmark::State& state) {
  lossForwardBackward(state, ps::TextureLossOptions());
}
BENCHMARK(BM_TextureLossForwardBackward)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The texture loss with every joint statistic of texture_ps.hpp weighted (their extra cost).
void BM_TextureLossForwardBackwardPs(benchmark::State& state) {
  ps::TextureLossOptions o;
  o.weights.psAutoLowpass = o.weights.psAutoMagnitude = o.weights.psCrossOrientation = 1.0f;
  o.weights.psCrossScale = o.weights.psColor = 1.0f;
  lossForwardBackward(state, o);
}
BENCHMARK(BM_TextureLossForwardBackwardPs)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The joint statistics alone (pyramid included), as computeTexturePsStatistics.
void BM_TexturePsStatistics(benchmark::State& state) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  const cv::Mat photo = texture(1, 1.0), mask = partMask();
  for (auto _ : state) benchmark::DoNotOptimize(ps::computeTexturePsStatistics(photo, mask));
}
BENCHMARK(BM_TexturePsStatistics)->Arg(1)->Unit(benchmark::kMillisecond);

// The placement term, forward + backward.
void BM_PlacementLoss(benchmark::State& state) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  const ps::PlacementLossTarget target(texture(1, 1.0), partMask());
  const cv::Mat render = texture(2, 2.0);
  cv::Mat grad;
  for (auto _ : state) benchmark::DoNotOptimize(ps::placementLoss(target, render, &grad));
}
BENCHMARK(BM_PlacementLoss)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_TextureKeyPs(benchmark::State& state) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  const cv::Mat photo = texture(1, 1.0), mask = partMask();
  ps::TextureKeyOptions o;
  o.psWeight = 1.0f;
  for (auto _ : state) benchmark::DoNotOptimize(ps::computeTextureKey(photo, mask, o));
}
BENCHMARK(BM_TextureKeyPs)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_TextureLossTarget(benchmark::State& state) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  const cv::Mat photo = texture(1, 1.0), mask = partMask();
  for (auto _ : state) {
    ps::TextureLossTarget target(photo, mask);
    benchmark::DoNotOptimize(target.normalizer());
  }
}
BENCHMARK(BM_TextureLossTarget)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_TextureKey(benchmark::State& state) {
  std::unique_ptr<ps::ThreadLimit> limit;
  threads(state, limit);
  const cv::Mat photo = texture(1, 1.0), mask = partMask();
  for (auto _ : state) benchmark::DoNotOptimize(ps::computeTextureKey(photo, mask));
}
BENCHMARK(BM_TextureKey)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
