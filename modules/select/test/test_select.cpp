#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "photoscene/core.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/select.hpp"

namespace ps {
namespace {

const GraphLibrary& library() {
  static const GraphLibrary lib = GraphLibrary::load();
  return lib;
}

const ExemplarBank& bank() {
  // the build tree's shared cache: built once per test run (the other tests wait on its lock)
  static const ExemplarBank b = ExemplarBank::loadOrBuild(
      library(), {}, std::filesystem::path(PS_BINARY_DIR) / "photoscene-cache");
  return b;
}

TEST(Select_Knn, flann_index_types_agree_with_exhaustive_search) {
  Rng rng(4);
  const int rows = 600, dim = 26;
  std::vector<float> keys(rows * dim);
  for (float& k : keys) k = rng.normal();
  const KnnIndex linear(keys, rows, dim, KnnIndexType::Linear);
  for (KnnIndexType type : {KnnIndexType::Linear, KnnIndexType::KdTree, KnnIndexType::KMeans}) {
    const KnnIndex index(keys, rows, dim, type);
    int agree = 0, total = 0;
    for (int q = 0; q < 50; ++q) {
      std::vector<float> query(dim);
      for (float& v : query) v = rng.normal();
      // brute force
      std::vector<std::pair<double, int>> all;
      for (int r = 0; r < rows; ++r) {
        double d = 0;
        for (int j = 0; j < dim; ++j) d += std::pow(query[j] - keys[r * dim + j], 2);
        all.push_back({std::sqrt(d), r});
      }
      std::sort(all.begin(), all.end());
      const KnnResult res = index.search(query, 5);
      ASSERT_EQ(res.index.size(), 5u);
      for (int i = 0; i < 5; ++i) {
        ++total;
        for (int j = 0; j < 5; ++j) agree += res.index[i] == all[j].second;
      }
      if (type == KnnIndexType::Linear) {
        EXPECT_EQ(res.index[0], all[0].second);
        EXPECT_NEAR(res.distance[0], all[0].first, 1e-4);
      }
    }
    // approximate indexes find most true neighbours at these settings. FLANN's trees differ from
    // run to run (seed_random does not pin them here): over 30 data seeds and two runs the k-d
    // tree's recall of the true 5 ranged 0.696-0.804, k-means' 0.872-0.948, so the bars sit
    // below those ranges (a broken index finds about 1 %: 5 of 600 rows at random)
    EXPECT_GE(static_cast<double>(agree) / total,
              type == KnnIndexType::Linear ? 1.0 : type == KnnIndexType::KdTree ? 0.6 : 0.75)
        << knnIndexTypeName(type);
  }
}

TEST(Select_Bank, cache_round_trip_and_invalidation) {
  ExemplarBankOptions small;
  small.drawsPerGraph = 1;
  small.uvScales = {2.0f};
  small.renderSize = 48;
  small.mapSize = 64;
  io::TempDir dir;
  bool cached = true;
  const ExemplarBank a = ExemplarBank::loadOrBuild(library(), small, dir.path(), &cached);
  EXPECT_FALSE(cached);
  Timer timer;
  const ExemplarBank b = ExemplarBank::loadOrBuild(library(), small, dir.path(), &cached);
  const double loadMs = timer.milliseconds();
  EXPECT_TRUE(cached);
  EXPECT_EQ(a.keys(), b.keys());
  EXPECT_EQ(a.graphNames(), b.graphNames());
  std::printf("bank of %d exemplars: built in %.2f s, loaded in %.2f ms\n", a.rows(),
              a.buildSeconds(), loadMs);
  const std::vector<float> q(a.dim(), 0.5f);
  EXPECT_EQ(a.select(q, 5).graph, b.select(q, 5).graph);
  // other options or another library: the file does not match and is not used
  ExemplarBankOptions other = small;
  other.seed = 9;
  EXPECT_EQ(ExemplarBank::load(dir / ExemplarBank::cacheFileName(library(), small),
                               library().contentHash(), other)
                .rows(),
            0);
  EXPECT_EQ(ExemplarBank::load(dir / ExemplarBank::cacheFileName(library(), small),
                               library().contentHash() + 1, small)
                .rows(),
            0);
  // a truncated file is refused, not trusted
  const auto file = dir / ExemplarBank::cacheFileName(library(), small);
  std::filesystem::resize_file(file, std::filesystem::file_size(file) / 2);
  EXPECT_EQ(ExemplarBank::load(file, library().contentHash(), small).rows(), 0);
}

/// A small exhaustive bank: `draws` per graph at 2 and 3 repeats, `observed` observed renderings
/// per draw, patches of `size` pixels from maps of 64.
ExemplarBankOptions smallBank(int draws, int observed, int size) {
  ExemplarBankOptions o;
  o.drawsPerGraph = draws;
  o.uvScales = {2.0f, 3.0f};
  o.observedPerDraw = observed;
  o.renderSize = size;
  o.mapSize = 64;
  o.indexType = KnnIndexType::Linear;
  return o;
}

TEST(Select_Bank, an_interrupted_build_saves_nothing_and_the_next_one_completes) {
  // Ctrl-C while the bank builds (a minute or more on a first run): ps::Interrupted out of the
  // build, no cache file (a half bank must never load), the lock given back for the next build
  const ExemplarBankOptions small = smallBank(1, 0, 32);
  io::TempDir dir;
  const auto file = dir / ExemplarBank::cacheFileName(library(), small);
  requestInterrupt();
  EXPECT_THROW(ExemplarBank::loadOrBuild(library(), small, dir.path()), Interrupted);
  clearInterrupt();
  EXPECT_FALSE(std::filesystem::exists(file));
  bool cached = true;
  const ExemplarBank b = ExemplarBank::loadOrBuild(library(), small, dir.path(), &cached);
  EXPECT_FALSE(cached);
  EXPECT_EQ(b.rows(), 2 * library().size());
  EXPECT_TRUE(std::filesystem::exists(file));
}

// The vote names each graph's nearest draw, and bankDrawValues gives that draw's values: a query
// rendered from one draw of a graph finds that draw again (the finalists' fits start there).
TEST(Select_Bank, the_vote_names_the_nearest_draw_and_its_values_reproduce_it) {
  io::TempDir dir;
  const std::vector<std::string> names = {"brick_red", "wood_planks", "tile_hexagon",
                                          "fabric_tartan", "stone_travertine"};
  for (const std::string& n : names)
    std::filesystem::copy_file(std::filesystem::path(GraphLibrary::defaultFolder()) / (n + ".json"),
                               dir.path() / (n + ".json"));
  const GraphLibrary lib = GraphLibrary::load(dir.path().string());
  const ExemplarBankOptions small = smallBank(5, 0, 64);
  const ExemplarBank b = ExemplarBank::build(lib, small);
  const cv::Mat mask(64, 64, CV_8UC1, cv::Scalar(255));
  int found = 0, asked = 0;
  for (const std::string& n : names)
    for (int d : {2, 4}) {
      MaterialGraph g = lib.create(n);
      g.setValues(bankDrawValues(g, small, d));
      const MaterialMaps maps = g.evaluate(64, MapSet::of({MapKind::Albedo, MapKind::Normal}));
      const GraphChoice c = b.select(
          describeTexture(renderCanonicalPatch(maps, 64, 2.0f, 0.f), mask, small), 40);
      for (const GraphVote& v : c.votes) {
        // nearestDraw is the draw of the graph's first (nearest) row among the neighbours
        int first = -1;
        for (int row : c.neighbours)
          if (b.graphNames()[b.exemplars()[row].graph] == v.graph) {
            first = b.exemplars()[row].draw;
            break;
          }
        EXPECT_EQ(v.nearestDraw, first) << v.graph;
        if (v.graph == n) {
          ++asked;
          found += v.nearestDraw == d;
        }
      }
    }
  // values that did not reproduce the bank's draw would find it 1 time in 5 by chance (at least
  // 6 of 10 by chance: 0.6 %); measured 7 of 10 (the bank's patches have random rotations, the
  // queries none: some draws of a graph look alike at some angle)
  EXPECT_EQ(asked, 10);
  EXPECT_GE(found, 6) << found << " of " << asked;
}

TEST(Select_Bank, distinct_draws_vote_once_through_their_nearest_rendering) {
  // 2 canonical scales + 1 observed rendering per draw: with distinctDraws, the k neighbours are
  // k different (graph, draw) pairs, each its nearest rendering, nearest first; the nearest
  // neighbour is the same as without it
  const ExemplarBankOptions small = smallBank(2, 1, 48);
  const ExemplarBank b = ExemplarBank::build(library(), small);
  EXPECT_EQ(b.maxRenderingsPerDraw(), 3);
  MaterialGraph g = library().create(library().names()[3]);
  const MaterialMaps maps = g.evaluate(64, MapSet::of({MapKind::Albedo, MapKind::Normal}));
  const cv::Mat mask(48, 48, CV_8UC1, cv::Scalar(255));
  const std::vector<float> key =
      describeTexture(renderCanonicalPatch(maps, 48, 2.5f, 30.f), mask, small);
  const int k = 7;
  const GraphChoice rows = b.select(key, k, false, false);
  const GraphChoice draws = b.select(key, k, false, true);
  ASSERT_EQ(draws.neighbours.size(), static_cast<size_t>(k));
  EXPECT_EQ(draws.neighbours[0], rows.neighbours[0]);
  std::set<std::pair<int, int>> ids;
  for (size_t i = 0; i < draws.neighbours.size(); ++i) {
    const Exemplar& e = b.exemplars()[draws.neighbours[i]];
    ids.insert({e.graph, e.draw});
    if (i > 0) {
      EXPECT_GE(draws.distances[i], draws.distances[i - 1]);
    }
  }
  EXPECT_EQ(ids.size(), static_cast<size_t>(k));
  // every rendering of a chosen draw is at least as far as the one that votes for it
  const std::vector<float> q = b.project(key);
  for (size_t i = 0; i < draws.neighbours.size(); ++i) {
    const Exemplar& chosen = b.exemplars()[draws.neighbours[i]];
    for (int r = 0; r < b.rows(); ++r) {
      const Exemplar& e = b.exemplars()[r];
      if (e.graph != chosen.graph || e.draw != chosen.draw) continue;
      double d = 0;
      for (int j = 0; j < b.indexDim(); ++j)
        d += std::pow(q[j] - b.keys()[static_cast<size_t>(r) * b.indexDim() + j], 2);
      EXPECT_GE(std::sqrt(d), draws.distances[i] - 1e-3);
    }
  }
  int votes = 0;
  for (const GraphVote& v : draws.votes) votes += v.count;
  EXPECT_EQ(votes, k);
}

TEST(Select_Bank, a_vote_within_a_category_is_the_nearest_rows_of_that_category) {
  // `parts.<name>.category`: the k nearest rows among the category's own, by exact distance in
  // the indexed key space, whichever category the query looks like
  const ExemplarBank& b = bank();
  const ExemplarBankOptions& o = b.options();
  MaterialGraph g = library().create("wood_planks");
  const MaterialMaps maps = g.evaluate(64, MapSet::of({MapKind::Albedo, MapKind::Normal}));
  const cv::Mat mask(64, 64, CV_8UC1, cv::Scalar(255));
  const std::vector<float> key =
      describeTexture(renderCanonicalPatch(maps, 64, 2.5f, 20.f), mask, o);
  const std::vector<float> q = b.project(key);
  const int k = 15;
  for (const std::string category : {"tile", "wood", "fabric"}) {
    const GraphChoice c = b.selectInCategory(key, k, category);
    std::vector<double> nearest;  // the category's distances, by brute force
    for (int r = 0; r < b.rows(); ++r) {
      if (b.categories()[b.exemplars()[r].graph] != category) continue;
      double d = 0;
      for (int j = 0; j < b.indexDim(); ++j)
        d += std::pow(q[j] - b.keys()[static_cast<size_t>(r) * b.indexDim() + j], 2);
      nearest.push_back(std::sqrt(d));
    }
    std::sort(nearest.begin(), nearest.end());
    ASSERT_EQ(c.neighbours.size(), static_cast<size_t>(k)) << category;
    for (int i = 0; i < k; ++i) {
      EXPECT_EQ(b.categories()[b.exemplars()[c.neighbours[i]].graph], category);
      EXPECT_NEAR(c.distances[i], nearest[i], 1e-4 * (1 + nearest[i])) << category << " " << i;
    }
    int votes = 0;
    for (const GraphVote& v : c.votes) {
      EXPECT_EQ(v.category, category);
      votes += v.count;
    }
    EXPECT_EQ(votes, k);
    EXPECT_EQ(c.category, category);
    // every graph of the category is listed once; those without a vote follow the voted ones,
    // nearest row first, each with the draw of that row
    std::map<std::string, std::pair<double, int>> nearestOf;  // graph -> (distance, its draw)
    for (int r = 0; r < b.rows(); ++r) {
      const int g = b.exemplars()[r].graph;
      if (b.categories()[g] != category) continue;
      double d = 0;
      for (int j = 0; j < b.indexDim(); ++j)
        d += std::pow(q[j] - b.keys()[static_cast<size_t>(r) * b.indexDim() + j], 2);
      const std::string& name = b.graphNames()[g];
      if (!nearestOf.count(name) || std::sqrt(d) < nearestOf[name].first)
        nearestOf[name] = {std::sqrt(d), b.exemplars()[r].draw};
    }
    ASSERT_EQ(c.votes.size(), nearestOf.size()) << category;
    std::set<std::string> listed;
    double previous = -1;
    for (size_t i = 0; i < c.votes.size(); ++i) {
      const GraphVote& v = c.votes[i];
      EXPECT_TRUE(listed.insert(v.graph).second) << v.graph;
      if (v.count > 0) {
        EXPECT_GT(v.weight, 0.0);
        EXPECT_TRUE(i == 0 || c.votes[i - 1].count > 0) << "a voted graph after an unvoted one";
        continue;
      }
      EXPECT_EQ(v.weight, 0.0);
      EXPECT_EQ(v.nearestDraw, nearestOf[v.graph].second) << v.graph;
      EXPECT_GE(nearestOf[v.graph].first, previous - 1e-4) << v.graph;
      previous = nearestOf[v.graph].first;
    }
  }
  // the unrestricted vote's nearest row is the nearest of its own category
  const GraphChoice any = b.select(key, k);
  const std::string own = b.categories()[b.exemplars()[any.neighbours[0]].graph];
  EXPECT_EQ(b.selectInCategory(key, k, own).neighbours[0], any.neighbours[0]);
  EXPECT_THROW(b.selectInCategory(key, k, "no_such_category"), Exception);
}

TEST(Select_Bank, held_out_draws_select_their_graph_and_category) {
  // Issue 5's protocol (canonical patches, random UV rotation and scale, random light color and
  // level; 59 graphs x 5 draws, seed 2024): top-1 >= 60%, category >= 85% asked. Measured with
  // the structure statistics, 10 canonical scales and 3 observed exemplars per draw: 82.0% /
  // 86.1% with the exact (linear) index this test uses, 80.3% / 85.8% kd-tree (6 scales and 2
  // observed: 77.6% / 84.1% exhaustive; before the structure statistics 59.7% / 67.1%); on the
  // development seed 777, 78.6% / 85.8% exhaustive. 295 draws: about +-2.3% (top-1) and +-2.0%
  // (category) one standard deviation. Both are asserted at the levels; category clears
  // 85% by 3 draws only (the exact index removes the kd-tree's build-to-build variation): seven
  // graphs (paint_eggshell, _glossy, _matte_wall, paper_white, plastic_glossy, _laminate,
  // _textured) are the same graph (fbm times a colour) with other fbm scales, which a random UV
  // scale and light colour make indistinguishable.
  const ExemplarBank& b = bank();
  const ExemplarBankOptions o;
  ASSERT_EQ(b.rows(), library().size() * o.drawsPerGraph *
                          (static_cast<int>(o.uvScales.size()) + o.observedPerDraw));
  const SelectionReport r = evaluateSelection(b, library(), o);
  std::printf("%s", r.table().c_str());
  EXPECT_GE(r.top1Accuracy(), 0.75);
  EXPECT_GE(r.categoryAccuracy(), 0.85);
}

TEST(Select_Bank, observed_parts_select_their_graph_and_category) {
  // What the pipeline meets: each held-out draw on a plane in perspective (tilt up to 65 deg),
  // with a shading gradient, blur, noise and often an odd mask, queried with its UVs through
  // selectForPart. With the canonical-only bank of before, this protocol gave 12.9% / 21.0%
  // (exhaustive search); with observed exemplars 34.9% / 41.0%; with the structure statistics
  // 39.7% / 47.5% exhaustive, 37.6% / 45.8% kd-tree (chance 1.7% / 6%). Assertions: the level
  // reached less about two to three standard deviations.
  HeldOutOptions h;
  h.observed = true;
  const SelectionReport r = evaluateSelection(bank(), library(), ExemplarBankOptions{}, h);
  std::printf("observed protocol\n%s", r.table().c_str());
  EXPECT_GE(r.top1Accuracy(), 0.33);
  EXPECT_GE(r.categoryAccuracy(), 0.40);
}

TEST(Select_Part, smooth_shading_is_removed_and_texture_kept) {
  // a stripe texture under a strong linear shading ramp: after removeSmoothShading the ramp is
  // gone (left and right halves have the same mean) and the stripes keep their contrast
  const int w = 160, h = 80;
  cv::Mat img(h, w, CV_32FC3), flat(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float stripe = (x / 4) % 2 ? 0.6f : 0.4f;
      flat.at<cv::Vec3f>(y, x) = cv::Vec3f(stripe, stripe, stripe);
      img.at<cv::Vec3f>(y, x) = flat.at<cv::Vec3f>(y, x) * std::exp(1.5f * x / w);
    }
  const cv::Mat mask(h, w, CV_8UC1, cv::Scalar(255));
  const cv::Mat out = removeSmoothShading(img, mask, 12.0);
  const cv::Scalar left = cv::mean(out(cv::Rect(8, 0, w / 2 - 8, h))),
                   right = cv::mean(out(cv::Rect(w / 2, 0, w / 2 - 8, h)));
  EXPECT_NEAR(left[0] / right[0], 1.0, 0.05);
  cv::Mat lum;
  cv::extractChannel(out, lum, 0);
  cv::Scalar m, sd;
  cv::meanStdDev(lum(cv::Rect(16, 0, w - 32, h)), m, sd);
  EXPECT_NEAR(sd[0] / m[0], 0.2, 0.04);  // the stripes' own relative contrast (0.1 / 0.5)
}

TEST(Select_Part, the_faces_of_one_part_meet_at_one_level_in_texture_space) {
  // Two faces of a box in one mask, one material (stripes of albedo 0.4 / 0.6 along u) under two
  // shading levels (1.0 and 0.35: a lit top and a side in shadow), each face its own UV chart.
  // Prepared for the key, both faces must come out at one level (the material's): a step
  // between them in texture space is an edge the material does not have (it read as planks).
  const int w = 160, h = 80;
  cv::Mat img(h, w, CV_32FC3), uv(h, w, CV_32FC2);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool side = x >= w / 2;
      const float u = (side ? 1.5f : 0.0f) + static_cast<float>(x % (w / 2)) / (w / 2);
      const float albedo = static_cast<int>(u * 16) % 2 ? 0.6f : 0.4f;
      const float shade = side ? 0.35f : 1.0f;
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(albedo, albedo, albedo) * shade;
      uv.at<cv::Vec2f>(y, x) = cv::Vec2f(u, static_cast<float>(y) / (w / 2));
    }
  const cv::Mat mask(h, w, CV_8UC1, cv::Scalar(255));
  const PartTexture t = preparePartTexture(img, mask, uv, cv::Mat(), 12.0);
  ASSERT_TRUE(t.unwarped);
  // the texture spans u in [0, 2.5): the first face on its left 40 %, the second on its right 40 %
  const int cols = t.image.cols, third = cols * 3 / 10;
  const cv::Rect left(0, 0, third, t.image.rows), right(cols - third, 0, third, t.image.rows);
  ASSERT_GT(cv::countNonZero(t.mask(left)), 100);
  ASSERT_GT(cv::countNonZero(t.mask(right)), 100);
  const double a = cv::mean(t.image(left), t.mask(left))[0],
               b = cv::mean(t.image(right), t.mask(right))[0];
  std::printf("face levels in texture space: %.4f, %.4f (photo: 0.5 and 0.175)\n", a, b);
  EXPECT_NEAR(b / a, 1.0, 0.03);
  // the stripes keep their contrast on both faces
  cv::Scalar m, sd;
  cv::Mat lum;
  cv::extractChannel(t.image, lum, 0);
  cv::meanStdDev(lum(right), m, sd, t.mask(right));
  EXPECT_NEAR(sd[0] / m[0], 0.2, 0.05);
}

TEST(Select_Part, unwarping_a_tilted_plane_covers_its_texture) {
  // One draw on a plane tilted by 60 degrees: the prepared texture is in texture space, its
  // coverage (after hole filling) is nearly the whole UV region the plane shows, values are
  // finite and positive. (Raw-key distances to the frontal view are printed for information: on
  // this case the unwarped key is not closer to the frontal one than the photo-frame key; the
  // bank's observed exemplars carry the remaining difference.)
  MaterialGraph g = library().create("tile_square_ceramic");
  const MaterialMaps maps = g.evaluate(256, MapSet::of({MapKind::Albedo, MapKind::Normal}));
  ObservedPlaneParams p;
  p.repeats = 3;
  const ObservedPlane frontal = renderObservedPlane(maps, p);
  p.tiltDeg = 60;
  p.yawDeg = 90;
  const ObservedPlane tilted = renderObservedPlane(maps, p);
  EXPECT_GT(cv::countNonZero(tilted.mask), static_cast<int>(tilted.mask.total() / 2));
  const PartTexture a =
      preparePartTexture(frontal.image, frontal.mask, frontal.uv, cv::Mat(), 12.0);
  const PartTexture b = preparePartTexture(tilted.image, tilted.mask, tilted.uv, cv::Mat(), 12.0);
  EXPECT_TRUE(a.unwarped && b.unwarped);
  // a tilted plane's UV region is a trapezoid (wide at the far side): over a third of the box
  EXPECT_GT(cv::countNonZero(b.mask), static_cast<int>(b.mask.total() / 3));
  double lo = 0, hi = 0;
  cv::minMaxLoc(b.image.reshape(1), &lo, &hi);
  EXPECT_TRUE(std::isfinite(lo) && std::isfinite(hi) && lo >= 0 && hi > 0);
  const double unwarped =
      descriptorDistance(computeTextureKey(a.image, a.mask), computeTextureKey(b.image, b.mask));
  const double photoFrame = descriptorDistance(computeTextureKey(frontal.image, frontal.mask),
                                               computeTextureKey(tilted.image, tilted.mask));
  std::printf("raw key distance frontal vs 60-degree tilt: photo frame %.3f, unwarped %.3f\n",
              photoFrame, unwarped);
  // bad input is refused at the boundary
  EXPECT_THROW(preparePartTexture(frontal.image, cv::Mat::zeros(frontal.mask.size(), CV_8UC1),
                                  frontal.uv, cv::Mat(), 12.0),
               Exception);
}

TEST(Select_Rules, homogeneous_threshold_scales_with_resolution) {
  EXPECT_EQ(homogeneousThreshold(320, 240), 1000);
  EXPECT_EQ(homogeneousThreshold(640, 480), 4000);
  EXPECT_EQ(homogeneousThreshold(160, 120, 1000), 250);
}

TEST(Select_Rules, thin_parts_show_no_interior_for_texture) {
  // A chair's frame: 6 bars 5 px wide, 100 px long (3000 px, three times the small-part
  // threshold at 320 x 240) has no pixel whose 7 x 7 window lies in it; a compact 55 x 55 part
  // of the same size keeps 49 x 49 of them. At 640 x 480 the window is 13 x 13, so the same
  // geometry drawn twice as large gives the same answer.
  for (const int s : {1, 2}) {
    cv::Mat frame = cv::Mat::zeros(240 * s, 320 * s, CV_8UC1),
            block = cv::Mat::zeros(240 * s, 320 * s, CV_8UC1);
    for (int b = 0; b < 6; ++b)
      frame(cv::Rect((20 + 15 * b) * s, 40 * s, 5 * s, 100 * s)).setTo(255);
    block(cv::Rect(100 * s, 100 * s, 55 * s, 55 * s)).setTo(255);
    EXPECT_EQ(cv::countNonZero(frame), 3000 * s * s);
    EXPECT_EQ(interiorPixels(frame), 0);
    const int inner = 55 * s - 2 * 3 * s;
    EXPECT_EQ(interiorPixels(block), inner * inner);
    EXPECT_GT(interiorPixels(block), homogeneousThreshold(320 * s, 240 * s));
    EXPECT_TRUE(isSmallPart(frame, 320 * s, 240 * s));
    EXPECT_FALSE(isSmallPart(block, 320 * s, 240 * s));
  }
  // a part that runs off the image has no window there: the edge's band is not interior
  cv::Mat full(240, 320, CV_8UC1, cv::Scalar(255));
  EXPECT_EQ(interiorPixels(full), (320 - 6) * (240 - 6));
  // one pixel, or none
  cv::Mat one = cv::Mat::zeros(240, 320, CV_8UC1);
  EXPECT_EQ(interiorPixels(one), 0);
  one.at<uchar>(120, 160) = 255;
  EXPECT_EQ(interiorPixels(one), 0);
  EXPECT_EQ(interiorPixels(cv::Mat()), 0);
}

}  // namespace
}  // namespace ps
