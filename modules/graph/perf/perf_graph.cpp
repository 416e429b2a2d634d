// Per graph: forward and forward + backward time at 256 and 1024, one thread.
// (Caches are cleared before every evaluation so every node runs.)
#include "photoscene/core.hpp"
#include "photoscene/graph.hpp"

#include <benchmark/benchmark.h>

namespace {

const ps::GraphLibrary& lib() {
  static const ps::GraphLibrary l = ps::GraphLibrary::load();
  return l;
}

void forward(benchmark::State& state, const std::string& name) {
  ps::ThreadLimit one(1);
  ps::MaterialGraph g = lib().create(name);
  const int n = int(state.range(0));
  for (auto _ : state) {
    g.clearCache();
    auto m = g.evaluate(n, ps::MapSet::of({ps::MapKind::Albedo, ps::MapKind::Normal, ps::MapKind::Roughness}));
    benchmark::DoNotOptimize(m.albedo.data);
  }
}

void forwardBackward(benchmark::State& state, const std::string& name) {
  ps::ThreadLimit one(1);
  ps::MaterialGraph g = lib().create(name);
  const int n = int(state.range(0));
  ps::MaterialMaps d;
  d.albedo = cv::Mat(n, n, CV_32FC3, cv::Scalar::all(1e-3));
  d.normal = cv::Mat(n, n, CV_32FC3, cv::Scalar::all(1e-3));
  d.roughness = cv::Mat(n, n, CV_32FC1, cv::Scalar::all(1e-3));
  for (auto _ : state) {
    g.clearCache();
    g.evaluate(n, ps::MapSet::of({ps::MapKind::Albedo, ps::MapKind::Normal, ps::MapKind::Roughness}));
    auto grad = g.backward(d);
    benchmark::DoNotOptimize(grad.data());
  }
}

const int registered = [] {
  for (const auto& name : lib().names()) {
    benchmark::RegisterBenchmark(("Graph_Forward/" + name).c_str(), forward, name)
        ->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Graph_ForwardBackward/" + name).c_str(), forwardBackward, name)
        ->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond);
  }
  return 0;
}();

}  // namespace
