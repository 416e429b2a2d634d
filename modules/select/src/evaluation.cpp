#include "photoscene/select/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "photoscene/core/rng.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/select/part_selection.hpp"

namespace ps {

std::string SelectionReport::table() const {
  std::string s;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "held-out selection: top-1 graph %.1f%%, category %.1f%% over %d draws\n",
                100 * top1Accuracy(), 100 * categoryAccuracy(), total);
  s += buf;
  s += "category confusion (rows: truth, columns: chosen)\n";
  std::vector<std::string> cats;
  for (const auto& [c, row] : categoryConfusion) cats.push_back(c);
  std::snprintf(buf, sizeof buf, "%-12s", "");
  s += buf;
  for (const auto& c : cats) {
    std::snprintf(buf, sizeof buf, " %5.5s", c.c_str());
    s += buf;
  }
  s += "\n";
  for (const auto& c : cats) {
    std::snprintf(buf, sizeof buf, "%-12s", c.c_str());
    s += buf;
    for (const auto& d : cats) {
      const auto& row = categoryConfusion.at(c);
      std::snprintf(buf, sizeof buf, " %5d", row.count(d) ? row.at(d) : 0);
      s += buf;
    }
    s += "\n";
  }
  s += "graphs right in fewer than half of their draws:";
  bool any = false;
  const int perGraph = total / std::max(1, static_cast<int>(correctPerGraph.size()));
  for (const auto& [n, k] : correctPerGraph) {
    if (2 * k < perGraph) {
      s += " " + n + "(" + std::to_string(k) + ")";
      any = true;
    }
  }
  if (!any) s += " none";
  return s + "\n";
}

SelectionReport evaluateSelection(const ExemplarBank& bank, const GraphLibrary& library,
                                  const ExemplarBankOptions& bankOptions, const HeldOutOptions& o) {
  SelectionReport r;
  const int size = bankOptions.renderSize;
  const cv::Mat mask(size, size, CV_8UC1, cv::Scalar(255));
  for (const std::string& name : library.names()) {
    // each graph's draws and views keyed by its name: a graph added to the library leaves the
    // others' held-out cases as they were
    const uint64_t key = Hasher().add(o.seed).add(std::string_view(name)).digest();
    Rng rng(key);
    MaterialGraph g = library.create(name);
    r.correctPerGraph[name] = 0;
    for (int d = 0; d < o.drawsPerGraph; ++d) {
      g.setValues(g.randomValues(mix64(key + 7919ULL * uint64_t(d)), o.spread));
      const MaterialMaps maps =
          g.evaluate(bankOptions.mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal}));
      const float scale = std::exp(rng.uniform(std::log(o.minUvScale), std::log(o.maxUvScale)));
      const float rot = rng.uniform(0.f, 360.f);
      const float level = std::exp(rng.uniform(std::log(o.minLevel), std::log(o.maxLevel)));
      cv::Vec3f light;
      for (int c = 0; c < 3; ++c)
        light[c] = level * rng.uniform(1 - o.colorJitter, 1 + o.colorJitter);
      PartSelectionOptions query;
      query.k = o.k;
      query.categoryFirst = o.categoryFirst;
      query.distinctDraws = o.distinctDraws;
      GraphChoice c;
      if (o.observed) {
        ObservedPlaneParams p = randomObservation(bankOptions.observation, rng);
        p.lightColor = light;
        const ObservedPlane obs = renderObservedPlane(maps, p);
        Timer t;
        c = selectForPart(bank, obs.image, obs.mask, obs.uv, cv::Mat(), query);
        r.querySeconds += t.seconds();
      } else {
        const cv::Mat patch = renderCanonicalPatch(maps, size, scale, rot, light);
        Timer t;
        c = selectForPart(bank, patch, mask, cv::Mat(), cv::Mat(), query);
        r.querySeconds += t.seconds();
      }

      ++r.total;
      const bool ok = c.graph == name;
      r.top1 += ok;
      r.correctPerGraph[name] += ok;
      r.category += c.category == g.category();
      r.categoryConfusion[g.category()][c.category]++;
    }
  }
  return r;
}

}  // namespace ps
