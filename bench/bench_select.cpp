// Graph selection benchmark: bank build time, index build and query time, and held-out accuracy
// (top-1 graph, category) for each FLANN index type against exhaustive search.
// Both held-out protocols: canonical patches (issue 5) and observed planes (perspective, shading,
// blur, noise, odd masks; queried with their UVs through selectForPart).
//   ps_bench_select [--draws N] [--scales a,b,c] [--size S] [--map M] [--k K] [--observed N]
//                   [--shading S] [--category-first 0|1] [--projection 0|1] [--linear-only 1]
//                   [--seed S (held-out draws; the test's: 2024)] [--observed-protocol 0|1]
//                   [--structure W] [--ps W (the texture key's joint statistics, features)] [--sweep-k 1 (k, distinct draws, category-first vote)]
//                   [--distinct 0|1 (1: the k nearest draws vote; default 0: the k nearest rows)]
//                   [--cache DIR] [--profile-only 1]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "bank_options.hpp"
#include "photoscene/core.hpp"
#include "photoscene/features.hpp"
#include "photoscene/select.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  ps::ExemplarBankOptions options;
  ps::HeldOutOptions held;
  bool linearOnly = false, observedProtocol = true, profileOnly = false, sweepK = false;
  std::string cache;
  CLI::App app{"Graph selection: bank build and query time, held-out accuracy per index type"};
  ps::bench::addBankOptions(app, options);
  app.add_option("--size", options.renderSize, "canonical patch size (px)");
  app.add_option("--map", options.mapSize, "graph evaluation size (px)");
  app.add_option("--ps", options.key.psWeight, "weight of the texture key's joint statistics");
  app.add_option("--structure", options.structureWeight, "weight of the structure statistics");
  app.add_option("--projection", options.discriminantProjection, "discriminant projection (0|1)");
  app.add_option("--k", held.k, "neighbours that vote");
  app.add_option("--heldout", held.drawsPerGraph, "held-out draws per graph");
  app.add_option("--seed", held.seed, "held-out draws' seed (the test's: 2024)");
  app.add_option("--category-first", held.categoryFirst, "vote for a category first (0|1)");
  app.add_option("--distinct", held.distinctDraws,
                 "1: the k nearest draws vote; 0 (default): the k nearest rows");
  app.add_option("--observed-protocol", observedProtocol, "also the observed-plane protocol (0|1)");
  app.add_option("--sweep-k", sweepK, "sweep k, distinct draws and the category-first vote (0|1)");
  app.add_option("--linear-only", linearOnly, "exhaustive search only (0|1)");
  app.add_option("--profile-only", profileOnly, "only where a query's time goes (0|1)");
  app.add_option("--cache", cache, "bank cache folder (default: build the bank)");
  CLI11_PARSE(app, argc, argv);
  const ps::GraphLibrary lib = ps::GraphLibrary::load();
  {
    // where a query's time goes (observed planes: unwarp, texture key, statistics, structure)
    ps::Rng rng(5);
    double tPrep = 0, tKey = 0, tAll = 0, tStruct = 0;
    const int n = 40;
    for (int i = 0; i < n; ++i) {
      ps::MaterialGraph g = lib.create(lib.names()[(i * 7) % lib.size()]);
      const ps::MaterialMaps maps =
          g.evaluate(options.mapSize, ps::MapSet::of({ps::MapKind::Albedo, ps::MapKind::Normal}));
      const ps::ObservedPlane obs =
          ps::renderObservedPlane(maps, ps::randomObservation(options.observation, rng));
      ps::Timer a;
      const ps::PartTexture tex =
          ps::preparePartTexture(obs.image, obs.mask, obs.uv, cv::Mat(), options.shadingSigma);
      tPrep += a.seconds();
      ps::Timer b;
      ps::computeTextureKey(tex.image, tex.mask, options.key);
      tKey += b.seconds();
      ps::Timer c;
      ps::computeStructureKey(tex.image, tex.mask, options.structure);
      tStruct += c.seconds();
      ps::Timer d;
      ps::describeTexture(tex.image, tex.mask, options);
      tAll += d.seconds();
    }
    std::printf(
        "observed query, ms each: prepare %.2f, texture key %.2f, structure %.2f, whole key %.2f\n",
        1e3 * tPrep / n, 1e3 * tKey / n, 1e3 * tStruct / n, 1e3 * tAll / n);
  }
  if (profileOnly) return 0;
  ps::Timer t;
  ps::ExemplarBank bank = cache.empty() ? ps::ExemplarBank::build(lib, options)
                                        : ps::ExemplarBank::loadOrBuild(lib, options, cache);
  std::printf("bank: %d graphs, %d exemplars x %d floats, built in %.2f s (%d threads)\n",
              lib.size(), bank.rows(), bank.dim(), t.seconds(), ps::maxThreads());
  std::printf("%-8s %12s %14s %10s %10s\n", "index", "build ms", "query us", "top-1 %",
              "category %");
  for (ps::KnnIndexType type :
       {ps::KnnIndexType::Linear, ps::KnnIndexType::KdTree, ps::KnnIndexType::KMeans}) {
    if (linearOnly && type != ps::KnnIndexType::Linear) continue;
    ps::Timer tb;
    bank.rebuildIndex(type);
    const double buildMs = tb.milliseconds();
    // pure kNN query time over the bank's own keys
    ps::Timer tq;
    const int queries = std::min(bank.rows(), 500);
    for (int q = 0; q < queries; ++q) {
      std::vector<float> key(bank.dim(), 0.1f * (q % 7));
      bank.select(key, held.k, held.categoryFirst, held.distinctDraws);
    }
    const double queryUs = tq.seconds() * 1e6 / queries;
    const ps::SelectionReport r = ps::evaluateSelection(bank, lib, options, held);
    std::printf("%-8s %12.2f %14.1f %10.1f %10.1f\n", ps::knnIndexTypeName(type), buildMs, queryUs,
                100 * r.top1Accuracy(), 100 * r.categoryAccuracy());
    if (type == ps::KnnIndexType::Linear) std::printf("%s", r.table().c_str());
    if (type == ps::KnnIndexType::Linear && sweepK) {
      for (int k : {5, 11, 21, 41})
        for (int distinct : {0, 1})
          for (int cf : {0, 1}) {
            ps::HeldOutOptions h = held;
            h.k = k;
            h.distinctDraws = distinct;
            h.categoryFirst = cf;
            const ps::SelectionReport q = ps::evaluateSelection(bank, lib, options, h);
            std::printf("sweep k %d distinctDraws %d categoryFirst %d: %.1f / %.1f\n", k, distinct,
                        cf, 100 * q.top1Accuracy(), 100 * q.categoryAccuracy());
          }
    }
  }
  if (!observedProtocol) return 0;
  // the observed protocol (what the pipeline meets), exhaustive search
  bank.rebuildIndex(ps::KnnIndexType::Linear);
  ps::HeldOutOptions obs = held;
  obs.observed = true;
  const ps::SelectionReport r = ps::evaluateSelection(bank, lib, options, obs);
  std::printf("observed protocol (linear): top-1 %.1f%%, category %.1f%%, %.2f ms per query\n%s",
              100 * r.top1Accuracy(), 100 * r.categoryAccuracy(),
              1e3 * r.querySeconds / std::max(1, r.total), r.table().c_str());
  return 0;
}
