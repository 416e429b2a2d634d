// Tests of the graph module: node gradients, library validity, tileability, resolution
// independence, output ranges, caching, self-fit with Adam.
#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"
#include "photoscene/graph.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace {

// The 1024 px sweeps below allocate every node's maps anew: reuse freed buffers (core/memory.hpp).
[[maybe_unused]] const bool kReuseImageMemory = (ps::reuseFreedImageMemory(), true);

const ps::GraphLibrary& lib() {
  static const ps::GraphLibrary l = ps::GraphLibrary::load(PS_SOURCE_DIR "/modules/graph/library");
  return l;
}

double meanAbs(const cv::Mat& a) {
  return cv::norm(a, cv::NORM_L1) / double(a.total() * a.channels());
}

}  // namespace

// ------------------------------------------------------------------ nodes
TEST(Graph_Nodes, catalog_has_at_least_25_types) {
  const auto cat = ps::nodeCatalog();
  EXPECT_GE(cat.size(), 25u);
  for (const auto& t : cat) {
    EXPECT_FALSE(t.doc.empty()) << t.name;
    EXPECT_FALSE(t.outputs.empty()) << t.name;
  }
}

// Tolerance (double): |a - fd| <= 1e-4 + 2e-2 max(|a|, |fd|), loss = mean of weighted maps,
// derivatives per unit of the normalized parameter, steps 1e-3, 3e-4, 1e-4 of the range.
namespace {
// Every node type of the catalogue at its default parameters.
void expectNodeGradientsMatch(const ps::GradientCheckOptions& o) {
  for (const auto& t : ps::nodeCatalog()) {
    const auto rep = ps::checkNodeGradients(t.name, {}, o);
    EXPECT_TRUE(rep.ok()) << t.name << ":\n" << rep.summary();
  }
}
}  // namespace

TEST(Graph_Nodes, gradients_match_finite_differences_double) {
  ps::GradientCheckOptions o;
  o.size = 32;
  o.absTol = 1e-4;
  expectNodeGradientsMatch(o);
}

// Same in float: looser (float FD noise ~1e-6 / step).
TEST(Graph_Nodes, gradients_match_finite_differences_float) {
  ps::GradientCheckOptions o;
  o.size = 32;
  o.doublePrecision = false;
  o.steps = {3e-3, 1e-3};
  o.relTol = 5e-2;
  o.absTol = 5e-4;
  expectNodeGradientsMatch(o);
}

TEST(Graph_Nodes, gradients_at_random_parameters) {
  ps::GradientCheckOptions o;
  o.size = 32;
  o.absTol = 1e-4;
  ps::Rng rng(5);
  for (const auto& t : ps::nodeCatalog()) {
    std::vector<float> v;
    for (const auto& p : t.params)
      for (int k = 0; k < p.dim; ++k) {
        // stay off the range ends so FD steps stay inside; discrete at defaults
        float x = p.defaultValue[k];
        if (p.differentiable()) x = p.min + (p.max - p.min) * (0.15f + 0.7f * rng.uniform());
        v.push_back(x);
      }
    const auto rep = ps::checkNodeGradients(t.name, v, o);
    EXPECT_TRUE(rep.ok()) << t.name << ":\n" << rep.summary();
  }
}

// fbm_bands with band_k = r^k is fbm with roughness r (the library's graphs were converted from
// fbm so: their default look must not change), and its gradient holds where rows run in
// parallel (the checks above use 32 px maps, which run serially).
TEST(Graph_Nodes, fbm_bands_reproduces_fbm_and_its_parallel_gradient) {
  auto graphWith = [](const std::string& noise) {
    const std::string s = R"({"name":"x","category":"paint","nodes":[)" + noise +
                          R"(,{"id":"c","type":"uniform_color"},
      {"id":"n","type":"normal","inputs":{"height":"f"}}],
      "outputs":{"albedo":"c","normal":"n","roughness":"f"}})";
    return ps::MaterialGraph::fromString(s, "x.json");
  };
  auto fbm = graphWith(
      R"({"id":"f","type":"fbm","params":{"scale_x":3,"scale_y":5,"octaves":6,"roughness":0.7,"seed":17}})");
  std::string bands =
      R"({"id":"f","type":"fbm_bands","params":{"scale_x":3,"scale_y":5,"octaves":6,"seed":17)";
  for (int k = 0; k < 6; ++k)
    bands += ",\"band_" + std::to_string(k) + "\":" + std::to_string(std::pow(0.7, k));
  auto fb = graphWith(bands + "}}");
  const cv::Mat a = fbm.evaluate(256).roughness, b = fb.evaluate(256).roughness;
  EXPECT_LT(cv::norm(a, b, cv::NORM_INF), 1e-5);
  EXPECT_GT(meanAbs(a - 0.5), 0.02);  // not flat

  ps::GradientCheckOptions o;
  o.size = 256;
  o.absTol = 1e-4;
  std::vector<float> v;
  for (const auto& p : ps::nodeCatalog())
    if (p.name == "fbm_bands")
      for (const auto& q : p.params) v.push_back(q.defaultValue[0]);
  ASSERT_FALSE(v.empty());
  const auto rep = ps::checkNodeGradients("fbm_bands", v, o);
  EXPECT_TRUE(rep.ok()) << rep.summary();
  // above the size whose octave planes forward keeps (6 x 512^2 values), backward regenerates
  // them: the same check on that path
  o.size = 512;
  const auto regenerated = ps::checkNodeGradients("fbm_bands", v, o);
  EXPECT_TRUE(regenerated.ok()) << regenerated.summary();
}

// The tile node's pattern_scale: stripes sampled into planks run pattern_scale times as often
// inside each plank (the planks themselves unchanged), and the gradient of what only `sampled`
// feeds (here the roughness) holds for pattern_scale and for row_offset, which moves where in
// its plank a pixel lies once the pattern is scaled.
TEST(Graph_Nodes, tile_pattern_scale_scales_the_grain_inside_each_tile) {
  auto planks = [](const char* direction, int cols) {
    return ps::MaterialGraph::fromString(std::string(R"({"name":"x","category":"wood","nodes":[
    {"id":"s","type":"stripes","params":{"count":16,"direction":")") +
                                             direction + R"(",
     "width":0.5,"softness":0.3}},
    {"id":"t","type":"tile","params":{"layout":"planks","rows":2,"cols":)" +
                                             std::to_string(cols) + R"(,"gap":0.02,"seed":3},
     "inputs":{"pattern":"s"}},
    {"id":"c","type":"uniform_color"},{"id":"n","type":"normal","inputs":{"height":"t.height"}}],
    "outputs":{"albedo":"c","normal":"n","roughness":"t.sampled"},
    "parameters":[{"name":"scale","targets":["t.pattern_scale"]},
                  {"name":"offset","targets":["t.row_offset"]}]})",
                                         "x.json");
  };
  auto g = planks("v", 1);
  // stripe edges crossed along a column (v): 2 per stripe, plus at most 2 per plank border
  auto crossings = [&](float scale) {
    g.setParameter("scale", {scale});
    const cv::Mat r = g.evaluate(256).roughness;
    int n = 0;
    for (int y = 1; y < r.rows; ++y)
      n += (r.at<float>(y, 40) > 0.5f) != (r.at<float>(y - 1, 40) > 0.5f);
    return n;
  };
  EXPECT_NEAR(crossings(1.0f), 32, 4);
  EXPECT_NEAR(crossings(2.0f), 64, 4);
  EXPECT_NEAR(crossings(0.5f), 16, 4);
  const cv::Mat h1 = g.evaluate(256).height;  // the planks do not move with the scale
  g.setParameter("scale", {1.0f});
  EXPECT_EQ(cv::norm(h1, g.evaluate(256).height, cv::NORM_INF), 0.0);

  // diagonal stripes, three planks a row: what a pixel samples moves with row_offset too
  auto d = planks("diagonal", 3);
  ps::GradientCheckOptions o;
  o.size = 64;
  o.absTol = 1e-5;
  for (float scale : {1.0f, 0.63f, 1.71f}) {  // off rational scales, whose samples sit on knots
    d.setParameter("scale", {scale});
    d.setParameter("offset", {0.37f});
    const auto rep = ps::checkGraphGradients(d, o);
    EXPECT_TRUE(rep.ok()) << "pattern_scale " << scale << ":\n" << rep.summary();
  }
}

// ------------------------------------------------------------------ library
TEST(Graph_Library, has_40_valid_graphs_in_spec_categories) {
  const auto& l = lib();
  EXPECT_GE(l.size(), 40);
  const auto& cats = ps::materialCategories();
  for (const auto& c : cats)
    EXPECT_FALSE(l.namesInCategory(c).empty()) << "no graph in category " << c;
  for (const auto& name : l.names()) {
    const auto& g = l.get(name);
    EXPECT_NE(std::find(cats.begin(), cats.end(), g.category()), cats.end()) << name;
    const int n = int(g.parameters().size()) - 1;  // without albedo_offset
    EXPECT_GE(n, 5) << name;
    EXPECT_LE(n, 40) << name;
    EXPECT_GE(g.findParameter("albedo_offset"), 0) << name;
    EXPECT_TRUE(g.hasOutput(ps::MapKind::Albedo) && g.hasOutput(ps::MapKind::Normal) &&
                g.hasOutput(ps::MapKind::Roughness));
  }
}

TEST(Graph_Library, env_var_and_argument_choose_the_folder) {
  const std::string dir = std::string(PS_BINARY_DIR) + "/graph_test_lib";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(PS_SOURCE_DIR "/modules/graph/library/homogeneous.json",
                             dir + "/homogeneous.json",
                             std::filesystem::copy_options::overwrite_existing);
  auto l = ps::GraphLibrary::load(dir);
  EXPECT_EQ(l.size(), 1);
  setenv("PHOTOSCENE_GRAPH_LIBRARY", dir.c_str(), 1);
  EXPECT_EQ(ps::GraphLibrary::defaultFolder(), dir);
  EXPECT_EQ(ps::GraphLibrary::load().size(), 1);
  unsetenv("PHOTOSCENE_GRAPH_LIBRARY");
  EXPECT_THROW(ps::GraphLibrary::load(dir + "/missing"), ps::InputError);
  EXPECT_THROW(lib().get("no_such_graph"), ps::InputError);
  EXPECT_NE(lib().contentHash(), l.contentHash());
}

// `draw_spread` scales how far random draws move a parameter: 0 keeps it at its default in every
// draw, 1 (the default) lets it roam its range; anything outside [0, 1] is an input error.
TEST(Graph_Format, draw_spread_scales_the_random_draws) {
  auto graph = [](const std::string& spread) {
    return ps::MaterialGraph::fromString(
        R"({"name":"x","category":"paint","nodes":[{"id":"c","type":"uniform_color"},
        {"id":"r","type":"uniform_gray","params":{"value":0.5}},
        {"id":"n","type":"normal","inputs":{"height":"r"}}],
        "parameters":[{"name":"level","targets":["r.value"])" +
            spread + R"(}],
        "outputs":{"albedo":"c","normal":"n","roughness":"r"}})",
        "s.json");
  };
  const auto held = graph(",\"draw_spread\":0"), free = graph("");
  double movedHeld = 0, movedFree = 0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    movedHeld += std::abs(held.randomValues(seed, 0.6f)[0] - 0.5f);
    movedFree += std::abs(free.randomValues(seed, 0.6f)[0] - 0.5f);
  }
  EXPECT_EQ(movedHeld, 0.0);
  EXPECT_GT(movedFree / 20, 0.05);
  EXPECT_THROW(graph(",\"draw_spread\":1.5"), ps::InputError);
  EXPECT_THROW(graph(",\"draw_spread\":\"x\""), ps::InputError);
}

TEST(Graph_Format, bad_files_are_input_errors) {
  const std::string ok = R"({"name":"x","category":"paint","nodes":[
    {"id":"c","type":"uniform_color"},{"id":"r","type":"uniform_gray"},
    {"id":"n","type":"normal","inputs":{"height":"r"}}],
    "outputs":{"albedo":"c","normal":"n","roughness":"r"}})";
  EXPECT_NO_THROW(ps::MaterialGraph::fromString(ok, "ok.json"));
  auto bad = [&](std::string from, std::string to) {
    std::string s = ok;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  EXPECT_THROW(ps::MaterialGraph::fromString(bad("paint", "lava"), "b.json"), ps::InputError);
  EXPECT_THROW(ps::MaterialGraph::fromString(bad("uniform_gray", "nope"), "b.json"),
               ps::InputError);
  EXPECT_THROW(
      ps::MaterialGraph::fromString(bad("\"albedo\":\"c\"", "\"albedo\":\"zz\""), "b.json"),
      ps::InputError);
  EXPECT_THROW(ps::MaterialGraph::fromString(bad("\"normal\":\"n\"", "\"normal\":\"r\""), "b.json"),
               ps::InputError);
  EXPECT_THROW(ps::MaterialGraph::fromString("{", "b.json"), ps::InputError);
  // a cycle
  const std::string cyc = R"({"name":"x","category":"paint","nodes":[
    {"id":"a","type":"invert","inputs":{"in":"b"}},{"id":"b","type":"invert","inputs":{"in":"a"}},
    {"id":"n","type":"normal","inputs":{"height":"a"}}],
    "outputs":{"albedo":"a","normal":"n","roughness":"a"}})";
  EXPECT_THROW(ps::MaterialGraph::fromString(cyc, "c.json"), ps::InputError);
  try {
    ps::MaterialGraph::fromString(bad("paint", "lava"), "b.json");
  } catch (const ps::InputError& e) {
    EXPECT_EQ(e.file(), "b.json");
    EXPECT_EQ(e.where(), "category");
  }
  // each error names where in the file it is
  const auto where = [&](const std::string& text) -> std::string {
    try {
      ps::MaterialGraph::fromString(text, "w.json");
    } catch (const ps::InputError& e) {
      return e.where();
    }
    return "(parsed)";
  };
  EXPECT_EQ(where(bad("\"height\":\"r\"", "\"height\":\"r.nope\"")), "nodes[2].inputs.height");
  EXPECT_EQ(where(bad("\"height\":\"r\"", "\"hue\":\"r\"")), "nodes[2].inputs.hue");
  EXPECT_EQ(where(bad("\"roughness\":\"r\"", "\"roughness\":\"c\"")), "outputs.roughness");
  EXPECT_EQ(where(bad(",\"roughness\":\"r\"", "")), "outputs.roughness");
  EXPECT_EQ(where(bad("\"id\":\"r\"", "\"id\":\"c\"")), "nodes[1].id");
  // ... and with one exposed parameter
  const auto withParameter = [&](const std::string& p) {
    return bad("\"roughness\":\"r\"}}", "\"roughness\":\"r\"},\"parameters\":[" + p + "]}");
  };
  EXPECT_EQ(where(withParameter(R"({"name":"k","targets":["r.value"]})")), "(parsed)");
  EXPECT_EQ(where(withParameter(R"({"name":"k","targets":["c.nope"]})")),
            "parameters[0].targets[0]");
  EXPECT_EQ(where(withParameter(R"({"name":"k","targets":["zz.value"]})")),
            "parameters[0].targets[0]");
  EXPECT_EQ(where(withParameter(R"({"name":"k","targets":["r.value","c.color"]})")),
            "parameters[0].targets[1]");
  EXPECT_EQ(where(withParameter(R"({"name":"albedo_offset","targets":["r.value"]})")),
            "parameters[0].name");
  EXPECT_EQ(where(withParameter(R"({"name":"k","targets":["r.value"],"min":2})")), "parameters[0]");
  EXPECT_EQ(where(withParameter(R"({"name":"k","targets":["r.value"],"default":"x"})")),
            "parameters[0].default");
  EXPECT_EQ(where(ok), "(parsed)");
}

// Every continuous parameter of every graph; double precision; same tolerance as the nodes.
TEST(Graph_Library, every_graph_gradient_matches_finite_differences) {
  ps::GradientCheckOptions o;
  o.size = 32;
  o.absTol = 1e-4;
  for (const auto& name : lib().names()) {
    ps::MaterialGraph g = lib().create(name);
    const auto rep = ps::checkGraphGradients(g, o);
    EXPECT_TRUE(rep.ok()) << name << ":\n" << rep.summary();
    g.setValues(g.randomValues(3, 0.3f));
    const auto rep2 = ps::checkGraphGradients(g, o);
    EXPECT_TRUE(rep2.ok()) << name << " (random values):\n" << rep2.summary();
  }
}

TEST(Graph_Library, outputs_in_range_for_random_parameters) {
  for (const auto& name : lib().names()) {
    ps::MaterialGraph g = lib().create(name);
    for (int s = 0; s < 3; ++s) {
      g.setValues(g.randomValues(100 + s, 1.0f));
      const auto m = g.evaluate(32);
      double lo, hi;
      for (const cv::Mat* map : {&m.albedo, &m.roughness, &m.metallic, &m.height}) {
        if (map->empty()) continue;
        ASSERT_TRUE(ps::allFinite(*map)) << name;
        cv::minMaxLoc(map->reshape(1), &lo, &hi);
        EXPECT_GE(lo, 0.0) << name;
        EXPECT_LE(hi, 1.0) << name;
      }
      ASSERT_TRUE(ps::allFinite(m.normal)) << name;
      for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
          const cv::Vec3f n = m.normal.at<cv::Vec3f>(y, x);
          ASSERT_NEAR(cv::norm(n), 1.0, 1e-4) << name;
          ASSERT_GT(n[2], 0.f) << name;
        }
    }
  }
}

// Wrap-around seam differences have the statistics of interior neighbor differences: the mean
// |difference| across the seam (column n-1 -> 0, row n-1 -> 0) is at most 1.3 x that across the
// worst interior column / row (patterns with period 1/k put a tile border on the seam, so the
// seam is compared with interior borders, not with the average), and a random shift of the
// texture leaves the mean interior difference unchanged within 10%.
TEST(Graph_Library, every_output_tiles) {
  const int n = 64;
  for (const auto& name : lib().names()) {
    ps::MaterialGraph g = lib().create(name);
    const auto m = g.evaluate(n);
    for (int k = 0; k < ps::kMapKindCount; ++k) {
      const cv::Mat& a = m.get(ps::MapKind(k));
      if (a.empty()) continue;
      const cv::Mat f = a.reshape(1, n);  // n rows, n*c cols
      const int c = a.channels();
      std::vector<double> colDiff(n, 0), rowDiff(n, 0);
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          for (int q = 0; q < c; ++q) {
            colDiff[x] +=
                std::abs(f.at<float>(y, ((x + 1) % n) * c + q) - f.at<float>(y, x * c + q));
            rowDiff[y] += std::abs(f.at<float>((y + 1) % n, x * c + q) - f.at<float>(y, x * c + q));
          }
      const double maxCol = *std::max_element(colDiff.begin(), colDiff.end() - 1);
      const double maxRow = *std::max_element(rowDiff.begin(), rowDiff.end() - 1);
      const double tol = 1e-3 * n * c;
      EXPECT_LE(colDiff[n - 1], 1.3 * maxCol + tol)
          << name << " " << ps::mapKindName(ps::MapKind(k)) << " u seam";
      EXPECT_LE(rowDiff[n - 1], 1.3 * maxRow + tol)
          << name << " " << ps::mapKindName(ps::MapKind(k)) << " v seam";
      // the texture rolled by (n/2 + 3, n/2 + 5): the interior mean must not change
      cv::Mat r(a.size(), a.type());
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          std::memcpy(r.ptr<float>((y + n / 2 + 5) % n) + ((x + n / 2 + 3) % n) * c,
                      a.ptr<float>(y) + x * c, sizeof(float) * c);
      cv::Mat dA = a.colRange(1, n) - a.colRange(0, n - 1),
              dR = r.colRange(1, n) - r.colRange(0, n - 1);
      EXPECT_NEAR(meanAbs(dR), meanAbs(dA), 0.1 * meanAbs(dA) + 1e-3)
          << name << " " << ps::mapKindName(ps::MapKind(k)) << " rolled";
    }
  }
}

// Issue 18's criterion, for every map of every graph: the mean |difference| across the wrap-around
// border (column n-1 -> 0, and row n-1 -> 0) is at most 2 x the mean |difference| between interior
// neighbours in the same direction, at 256 and at 1024 px (stone_slate's roughness measured 0.096
// across the border against 0.015 inside at 1024 before it was fixed). Stricter than
// every_output_tiles, which compares with the worst interior line: a tile joint on the border
// passes that one and fails this one, so tile-like graphs move their pattern by half a tile
// (make_library.py, finish(shift=...)) and the border runs through tiles, as most lines do.
namespace {
struct BorderGradient {
  double borderU, interiorU, borderV, interiorV;
};
BorderGradient borderGradient(const cv::Mat& a) {
  const int n = a.rows, c = a.channels();
  const cv::Mat f = a.reshape(1, n);
  double bu = 0, iu = 0, bv = 0, iv = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int q = 0; q < c; ++q) {
        const float v = f.at<float>(y, x * c + q);
        const double du = std::abs(f.at<float>(y, ((x + 1) % n) * c + q) - v);
        const double dv = std::abs(f.at<float>((y + 1) % n, x * c + q) - v);
        (x == n - 1 ? bu : iu) += du;
        (y == n - 1 ? bv : iv) += dv;
      }
  const double cnt = double(n) * c;
  return {bu / cnt, iu / (cnt * (n - 1)), bv / cnt, iv / (cnt * (n - 1))};
}
}  // namespace

// Two criteria on the same evaluations (each graph at 256 and 1024 px, every map; computed once,
// as the two 1024 px sweeps of the library took 41 + 38 s of CI when they were separate tests):
// - border continuity: issue 18's bound above, at 256 and at 1024 px;
// - resolution independence: 1024 box-downsampled to 256 vs 256, both low-passed (gaussian sigma
//   2 px at 256): mean absolute difference < 0.03 for albedo and roughness, < 0.08 for normals
//   (slopes of octaves above the 256 px Nyquist limit alias differently).
TEST(Graph_Library, border_continuity_within_2x_interior_gradient_and_resolution_independent) {
  for (const auto& name : lib().names()) {
    ps::MaterialGraph g = lib().create(name);
    const ps::MaterialMaps lo = g.evaluate(256);
    const ps::MaterialMaps hi = g.evaluate(1024);
    for (const auto* maps : {&lo, &hi}) {
      for (int k = 0; k < ps::kMapKindCount; ++k) {
        const cv::Mat& a = maps->get(ps::MapKind(k));
        if (a.empty()) continue;
        const auto b = borderGradient(a);
        const std::string what =
            name + " " + ps::mapKindName(ps::MapKind(k)) + " at " + std::to_string(a.rows);
        const double tol = 1e-4;
        EXPECT_LE(b.borderU, 2.0 * b.interiorU + tol)
            << what << " u border " << b.borderU << " interior " << b.interiorU;
        EXPECT_LE(b.borderV, 2.0 * b.interiorV + tol)
            << what << " v border " << b.borderV << " interior " << b.interiorV;
      }
    }
    for (auto k : {ps::MapKind::Albedo, ps::MapKind::Roughness, ps::MapKind::Normal}) {
      cv::Mat d, a, b;
      cv::resize(hi.get(k), d, cv::Size(256, 256), 0, 0, cv::INTER_AREA);
      cv::GaussianBlur(d, a, cv::Size(0, 0), 2.0, 2.0, cv::BORDER_REFLECT);
      cv::GaussianBlur(lo.get(k), b, cv::Size(0, 0), 2.0, 2.0, cv::BORDER_REFLECT);
      const double err = meanAbs(a - b);
      EXPECT_LT(err, k == ps::MapKind::Normal ? 0.08 : 0.03) << name << " " << ps::mapKindName(k);
    }
  }
}

TEST(Graph_Engine, caches_unchanged_nodes_and_computes_only_requested_outputs) {
  ps::MaterialGraph g = lib().create("wood_planks");
  g.evaluate(64, ps::MapSet::of({ps::MapKind::Roughness}));
  const auto r1 = g.nodeRuns();
  g.evaluate(64, ps::MapSet::of({ps::MapKind::Roughness}));
  EXPECT_EQ(g.nodeRuns(), r1);  // nothing changed
  g.evaluate(64);
  const auto r2 = g.nodeRuns();
  EXPECT_GT(r2, r1);  // albedo / normal nodes ran now
  g.setParameter("roughness_max", {0.3f});
  g.evaluate(64);
  EXPECT_EQ(g.nodeRuns(), r2 + 1);  // only the roughness levels node
  g.setParameter("albedo_offset", {0.1f, 0.f, 0.f});
  g.evaluate(64);
  EXPECT_EQ(g.nodeRuns(), r2 + 1);  // the offset is applied after the nodes
  g.clearCache();
  g.evaluate(64);
  EXPECT_GT(g.nodeRuns(), r2 + 1);
}

TEST(Graph_Engine, albedo_offset_shifts_albedo_and_same_seed_same_values) {
  ps::MaterialGraph g = lib().create("paint_matte_wall");
  const auto a = g.evaluate(32).albedo.clone();
  g.setParameter("albedo_offset", {0.05f, 0.f, -0.05f});
  const auto b = g.evaluate(32).albedo;
  EXPECT_NEAR(cv::mean(b)[0] - cv::mean(a)[0], 0.05, 1e-4);
  EXPECT_NEAR(cv::mean(b)[2] - cv::mean(a)[2], -0.05, 1e-4);
  EXPECT_EQ(g.randomValues(9), g.randomValues(9));
  EXPECT_NE(g.randomValues(9), g.randomValues(10));
}

// ------------------------------------------------------------------ self-fit
namespace {
struct FitResult {
  double initial, final;
};
FitResult selfFit(ps::MaterialGraph& g, uint64_t seed, int iters, int size) {
  const std::vector<float> target = g.randomValues(seed, 0.5f);
  g.setValues(target);
  const auto t = g.evaluate(
      size, ps::MapSet::of({ps::MapKind::Albedo, ps::MapKind::Normal, ps::MapKind::Roughness}));
  const ps::MaterialMaps tm{t.albedo.clone(), t.normal.clone(), t.roughness.clone(), {}, {}};
  // perturbed start: every continuous value moved by up to 20% of its range; discrete kept
  std::vector<float> x = target;
  ps::Rng rng(seed + 99);
  const auto mask = g.differentiableMask();
  std::vector<float> range(x.size(), 1.f);
  for (const auto& p : g.parameters())
    for (int k = 0; k < p.dim; ++k) range[p.offset + k] = p.max - p.min;
  for (size_t i = 0; i < x.size(); ++i)
    if (mask[i]) x[i] += range[i] * 0.2f * (rng.uniform() * 2 - 1);
  x = g.projectValues(x);
  auto lossAndGrad = [&](std::vector<float>* grad) {
    g.setValues(x);
    const auto m = g.evaluate(
        size, ps::MapSet::of({ps::MapKind::Albedo, ps::MapKind::Normal, ps::MapKind::Roughness}));
    double L = 0;
    ps::MaterialMaps d;
    for (auto k : {ps::MapKind::Albedo, ps::MapKind::Normal, ps::MapKind::Roughness}) {
      cv::Mat diff = m.get(k) - tm.get(k);
      const double cnt = double(diff.total() * diff.channels());
      L += diff.dot(diff) / cnt;
      d.get(k) = diff * (2.0 / cnt);
    }
    if (grad) *grad = g.backward(d);
    return L;
  };
  const double L0 = lossAndGrad(nullptr);
  // Adam in normalized parameter units
  std::vector<double> m1(x.size(), 0), m2(x.size(), 0);
  const double lr = 0.01, b1 = 0.9, b2 = 0.999;
  double best = L0;
  for (int it = 1; it <= iters; ++it) {
    std::vector<float> gr;
    best = std::min(best, lossAndGrad(&gr));
    for (size_t i = 0; i < x.size(); ++i) {
      if (!mask[i]) continue;
      const double gi = gr[i] * range[i];
      m1[i] = b1 * m1[i] + (1 - b1) * gi;
      m2[i] = b2 * m2[i] + (1 - b2) * gi * gi;
      const double mh = m1[i] / (1 - std::pow(b1, it)), vh = m2[i] / (1 - std::pow(b2, it));
      x[i] -= float(range[i] * lr * mh / (std::sqrt(vh) + 1e-8));
    }
    x = g.projectValues(x);
  }
  best = std::min(best, lossAndGrad(nullptr));
  return {L0, best};
}
}  // namespace

TEST(Graph_Library, self_fit_with_adam_reduces_error_for_most_graphs) {
  int pass = 0, total = 0;
  std::string failed;
  for (const auto& name : lib().names()) {
    ps::MaterialGraph g = lib().create(name);
    const FitResult r = selfFit(g, 7, 120, 32);
    const double red = r.initial > 0 ? 1.0 - r.final / r.initial : 1.0;
    ++total;
    if (red >= 0.9)
      ++pass;
    else
      failed += "  " + name + ": " + std::to_string(int(red * 100)) + "% (loss " +
                std::to_string(r.initial) + " -> " + std::to_string(r.final) + ")\n";
    EXPECT_LE(r.final, r.initial + 1e-12) << name;
  }
  std::printf("self-fit: %d / %d graphs reduce the map error by >= 90%%\n%s", pass, total,
              failed.c_str());
  EXPECT_GE(pass, int(0.75 * total)) << failed;
}

// ------------------------------------------------------------------ palette prior
namespace {
// A colour turned by `turn` radians in Oklab's chroma plane, lightness and chroma kept.
std::vector<float> turnHue(const float* rgb, double turn) {
  // Oklab by its published matrices, independent of the module's copy
  const double M1[3][3] = {{0.4122214708, 0.5363325363, 0.0514459929},
                           {0.2119034982, 0.6806995451, 0.1073969566},
                           {0.0883024619, 0.2817188376, 0.6299787005}};
  const double M2[3][3] = {{0.2104542553, 0.7936177850, -0.0040720468},
                           {1.9779984951, -2.4285922050, 0.4505937099},
                           {0.0259040371, 0.7827717662, -0.8086757660}};
  double r[3], lab[3];
  for (int i = 0; i < 3; ++i)
    r[i] = std::cbrt(M1[i][0] * rgb[0] + M1[i][1] * rgb[1] + M1[i][2] * rgb[2]);
  for (int k = 0; k < 3; ++k) lab[k] = M2[k][0] * r[0] + M2[k][1] * r[1] + M2[k][2] * r[2];
  const double a = lab[1] * std::cos(turn) - lab[2] * std::sin(turn);
  const double b = lab[1] * std::sin(turn) + lab[2] * std::cos(turn);
  const cv::Matx33d m2(M2[0][0], M2[0][1], M2[0][2], M2[1][0], M2[1][1], M2[1][2], M2[2][0],
                       M2[2][1], M2[2][2]);
  const cv::Matx33d m1(M1[0][0], M1[0][1], M1[0][2], M1[1][0], M1[1][1], M1[1][2], M1[2][0],
                       M1[2][1], M1[2][2]);
  cv::Vec3d q = m2.inv() * cv::Vec3d(lab[0], a, b);
  for (int i = 0; i < 3; ++i) q[i] = q[i] * q[i] * q[i];
  const cv::Vec3d c = m1.inv() * q;
  return {float(c[0]), float(c[1]), float(c[2])};
}
}  // namespace

TEST(Graph_Palette, ramps_are_found_and_the_prior_is_zero_at_the_defaults) {
  const ps::MaterialGraph wood = lib().create("wood_planks");
  const auto ramps = wood.colorRamps();
  ASSERT_EQ(ramps.size(), 1u);
  ASSERT_EQ(ramps[0].size(), 3u);  // wood_dark, wood_mid, wood_light
  for (int i : ramps[0]) EXPECT_EQ(wood.parameters()[size_t(i)].dim, 3);
  EXPECT_NEAR(ps::paletteLoss(wood, wood.defaultValues()), 0.0, 1e-12);
  // a graph whose colours are separate uniform colours has no ramp, and no prior
  const ps::MaterialGraph paint = lib().create("paint_matte_wall");
  EXPECT_TRUE(paint.colorRamps().empty());
  EXPECT_EQ(ps::paletteLoss(paint, paint.randomValues(3)), 0.0);
  int withRamps = 0;
  for (const auto& name : lib().names()) withRamps += lib().get(name).colorRamps().empty() ? 0 : 1;
  EXPECT_GE(withRamps, 20);  // the colors3 ramps of make_library.py
}

TEST(Graph_Palette, the_ramp_may_turn_as_a_whole_but_not_apart) {
  ps::MaterialGraph g = lib().create("wood_planks");
  const auto ramp = g.colorRamps().at(0);
  const std::vector<float> v0 = g.defaultValues();
  // all three colours turned together (brown to red, to olive): nearly free. Not exactly 0: the
  // chroma differences between the colours turn with them
  for (double turn : {-0.5, 0.3, 0.8}) {
    std::vector<float> v = v0;
    for (int i : ramp) {
      const int off = g.parameters()[size_t(i)].offset;
      const auto c = turnHue(&v0[size_t(off)], turn);
      std::copy(c.begin(), c.end(), v.begin() + off);
    }
    // the same turn on the dark colour alone: the drift the prior is for
    std::vector<float> apart = v0;
    const int off = g.parameters()[size_t(ramp[0])].offset;
    const auto c = turnHue(&v0[size_t(off)], turn);
    std::copy(c.begin(), c.end(), apart.begin() + off);
    const double together = ps::paletteLoss(g, v), alone = ps::paletteLoss(g, apart);
    EXPECT_GT(alone, 4 * together) << "turn " << turn;
    EXPECT_GT(alone, 1e-4) << "turn " << turn;
  }
  // the whole ramp made brighter (every colour x 1.5, clamped at 1): lightness is free, and the
  // chroma differences that the brightening scales stay small
  std::vector<float> brighter = v0;
  for (int i : ramp)
    for (int k = 0; k < 3; ++k) {
      const int o = g.parameters()[size_t(i)].offset + k;
      brighter[size_t(o)] = std::min(1.f, v0[size_t(o)] * 1.5f);
    }
  EXPECT_LT(ps::paletteLoss(g, brighter), 2e-4);
}

TEST(Graph_Palette, all_colours_hold_a_lone_colour_with_the_others) {
  // concrete_ribbed_panels: a ramp for the panels (dark / mid / light) and a separate joint
  // colour. Turning the joint alone to purple is no ramp's business; with all colours as one
  // group it costs as a ramp colour's drift does, and turning every colour together stays cheap
  ps::MaterialGraph g = lib().create("concrete_ribbed_panels");
  const int joint = g.findParameter("joint_color");
  ASSERT_GE(joint, 0);
  const auto groups = ps::paletteGroups(g, ps::PaletteScope::AllColours);
  ASSERT_EQ(groups.size(), 1u);
  EXPECT_EQ(groups[0].size(), 4u);  // panel_dark, panel_mid, panel_light, joint_color
  EXPECT_EQ(std::count(groups[0].begin(), groups[0].end(), g.findParameter("albedo_offset")), 0);
  const std::vector<float> v0 = g.defaultValues();
  EXPECT_NEAR(ps::paletteLoss(g, v0, nullptr, ps::PaletteScope::AllColours), 0.0, 1e-12);
  std::vector<float> purple = v0;
  const int off = g.parameters()[size_t(joint)].offset;
  purple[size_t(off)] = 0.09f, purple[size_t(off + 1)] = 0.0f, purple[size_t(off + 2)] = 0.18f;
  EXPECT_NEAR(ps::paletteLoss(g, purple, nullptr, ps::PaletteScope::Ramps), 0.0, 1e-12);
  const double lone = ps::paletteLoss(g, purple, nullptr, ps::PaletteScope::AllColours);
  EXPECT_GT(lone, 1e-3);
  std::vector<float> together = v0;
  for (int i : groups[0]) {
    const int o = g.parameters()[size_t(i)].offset;
    const auto c = turnHue(&v0[size_t(o)], 0.6);
    std::copy(c.begin(), c.end(), together.begin() + o);
  }
  EXPECT_LT(ps::paletteLoss(g, together, nullptr, ps::PaletteScope::AllColours), 0.25 * lone);
}

TEST(Graph_Palette, a_dead_zone_frees_the_draws_and_still_holds_a_lone_colour) {
  // every graph's own random draws (the exemplar bank's spread) cost nothing with the dead zone,
  // so a fit to a draw is not pulled off it; the purple joint still costs
  int zero = 0, total = 0;
  for (const auto& name : lib().names()) {
    ps::MaterialGraph g = lib().create(name);
    if (ps::paletteGroups(g, ps::PaletteScope::AllColours).empty()) continue;
    for (uint64_t d = 0; d < 8; ++d, ++total)
      zero += ps::paletteLoss(g, g.randomValues(5000 + d, 0.6f), nullptr,
                              ps::PaletteScope::AllColours, ps::kPaletteDrawDeadZone) == 0.0;
  }
  EXPECT_GE(zero, 0.98 * total) << zero << " of " << total << " draws cost nothing";
  ps::MaterialGraph g = lib().create("concrete_ribbed_panels");
  std::vector<float> purple = g.defaultValues();
  const int off = g.parameters()[size_t(g.findParameter("joint_color"))].offset;
  purple[size_t(off)] = 0.09f, purple[size_t(off + 1)] = 0.0f, purple[size_t(off + 2)] = 0.18f;
  EXPECT_GT(
      ps::paletteLoss(g, purple, nullptr, ps::PaletteScope::AllColours, ps::kPaletteDrawDeadZone),
      1e-3);
}

TEST(Graph_Palette, gradient_matches_finite_differences_and_stays_finite_at_black) {
  // (the colours and the albedo offset, at random draws whose ramps are pulled apart; without
  // and with the dead zone)
  for (const float dz : {0.0f, ps::kPaletteDrawDeadZone})
    for (const ps::PaletteScope scope : {ps::PaletteScope::Ramps, ps::PaletteScope::AllColours})
      for (const char* name :
           {"wood_planks", "brick_red", "stone_slate", "fabric_velvet", "concrete_ribbed_panels"}) {
        ps::MaterialGraph g = lib().create(name);
        const auto ramps = ps::paletteGroups(g, scope);
        ASSERT_FALSE(ramps.empty()) << name;
        for (uint64_t seed : {1u, 2u, 3u}) {
          std::vector<float> v = g.randomValues(seed, 1.0f);
          // push the ramp colours apart, so the loss is not near its minimum
          ps::Rng rng(seed);
          for (int i : ramps[0])
            for (int k = 0; k < 3; ++k) {
              float& x = v[size_t(g.parameters()[size_t(i)].offset + k)];
              x = std::clamp(x + 0.3f * (rng.uniform() - 0.5f), 0.05f, 0.95f);
            }
          std::vector<float> grad;
          const double l = ps::paletteLoss(g, v, &grad, scope, dz);
          ASSERT_GT(l, 0) << name;
          std::vector<int> checked = ramps[0];
          checked.push_back(g.findParameter("albedo_offset"));  // the colours are seen through it
          for (int i : checked)
            for (int k = 0; k < 3; ++k) {
              const size_t o = size_t(g.parameters()[size_t(i)].offset + k);
              const float h = 1e-3f;
              std::vector<float> a = v, b = v;
              a[o] += h, b[o] -= h;
              const double fd = (ps::paletteLoss(g, a, nullptr, scope, dz) -
                                 ps::paletteLoss(g, b, nullptr, scope, dz)) /
                                (2 * h);
              EXPECT_NEAR(grad[o], fd, 2e-3 * std::max(1.0, std::abs(fd)) + 1e-4)
                  << name << " value " << o;
            }
          for (size_t o = 0; o < grad.size(); ++o) EXPECT_TRUE(std::isfinite(grad[o]));
        }
        // black and white ramp colours: finite loss and gradient
        std::vector<float> v = g.defaultValues();
        const auto& ramp = ramps[0];
        for (int k = 0; k < 3; ++k) {
          v[size_t(g.parameters()[size_t(ramp[0])].offset + k)] = 0.f;
          v[size_t(g.parameters()[size_t(ramp.back())].offset + k)] = 1.f;
        }
        std::vector<float> grad;
        EXPECT_TRUE(std::isfinite(ps::paletteLoss(g, v, &grad, scope, dz))) << name;
        for (float x : grad) EXPECT_TRUE(std::isfinite(x)) << name;
      }
}
