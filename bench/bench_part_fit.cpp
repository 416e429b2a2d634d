// Run time against error of the per-part material fit: synthetic parts (graphs x lightings) fitted
// with each preset and each iteration budget; prints a table (time per part, texture-feature
// distance, mean-albedo error, UV rotation / scale error against the truth) and, with --plot,
// draws error against seconds into a PNG (OpenCV imgproc, no Python).
//
//   ps_bench_part_fit [presets (comma list, default fast,balanced)] [graphs (default
//   wood_planks,tile_checker)]
//                     [--iters 30,60,120 (budgets; 0 = the preset's own; default 0)]
//                     [--lights 12,30] [--size 160x120] [--threads 1 (0 = all)]
//                     [--set "key=value;..." (PartFitOptions fields after the preset, e.g.
//                     placementWeight, psAutoLowpass)]
//                     [--start-truth (start from the true UV transform)]
//                     [--renders DIR (writes <graph>_<light>_photo.png and
//                     <graph>_<light>_<preset>_<budget>.png)]
//                     [--checkpoints 50,100,200 (also a row at each of these Adam steps of one run:
//                     the best state so far, with the time so far; the same as a run with that
//                     budget only for presets without a coarse phase, i.e. `paper`)]
//                     [--plot file.png] [--csv file.csv] [--add-csv earlier.csv (rows added to the
//                     plot)]
//
// "seconds" is wall time of fitPart, "cpu" the process CPU time over the same call (with one
// thread, the number to compare on a loaded machine).
//
// Errors against the truth, the same for every preset: each fit (graph values, UV transform, mean
// roughness) is rendered by the render layer with paper's settings (maps 256, specularSub 2, full
// resolution), and so is the truth (its own roughness map). "to truth" is the texture-feature
// distance between the two noise-free renders; "yardstick" the distance from the fit's render to
// the photo (what the fit minimises, photo noise included: a fit can go below the truth's own value
// there by fitting the noise); "mean albedo err" compares the graphs' mean albedo at 256;
// "placement to truth" is ps::placementLoss (sigma 2) between the two noise-free renders: where the
// pattern lies (UV offset, rotation of seams and grout), which the texture distance cannot see.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgproc.hpp>

#include "photoscene/core/parallel.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/features/texture_placement.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/optim.hpp"
#include "../modules/render/test/synthetic_room.hpp"

using namespace ps;
using namespace ps::testroom;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

struct Row {
  std::string graph, preset;
  float light = 0;
  int budget = 0;
  double seconds = 0, cpu = 0, texStart = 0, texEnd = 0, atTruth = 0, albedoErr = 0, rot = 0, rot90 = 0, scale = 0;
  double yardstick = 0, toTruth = 0;
  double placement = 0;  // 1 - correlation of the low-passed luminances of fit and truth renders
  int iterations = 0, candidates = 0;
};

// Error against CPU seconds (one thread: wall time on a quiet machine), log-log, one marker per run: colour = preset, shape = graph; left panel the
// texture-feature distance, right panel the mean-albedo error.
void plot(const std::vector<Row>& rows, const std::string& path) {
  const int W = 1180, H = 560, panelW = 500, panelH = 400, top = 50, left0 = 70, gap = 580;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::vector<cv::Scalar> palette = {{200, 80, 30}, {30, 140, 30}, {30, 30, 200}, {150, 30, 150}, {0, 150, 200}};
  // one shape per graph: circle, square, triangle, diamond, cross
  auto marker = [&](const cv::Point& p, int shape, const cv::Scalar& col) {
    switch (shape % 5) {
      case 0: cv::circle(img, p, 5, col, 2, cv::LINE_AA); break;
      case 1: cv::rectangle(img, p - cv::Point(4, 4), p + cv::Point(4, 4), col, 2); break;
      case 2: cv::drawMarker(img, p, col, cv::MARKER_TRIANGLE_UP, 11, 2); break;
      case 3: cv::drawMarker(img, p, col, cv::MARKER_DIAMOND, 11, 2); break;
      default: cv::drawMarker(img, p, col, cv::MARKER_TILTED_CROSS, 10, 2); break;
    }
  };
  std::map<std::string, int> presetIdx, graphIdx;
  for (const Row& r : rows) {
    presetIdx.emplace(r.preset, static_cast<int>(presetIdx.size()));
    graphIdx.emplace(r.graph, static_cast<int>(graphIdx.size()));
  }
  double smin = 1e30, smax = 0;
  for (const Row& r : rows) smin = std::min(smin, r.cpu), smax = std::max(smax, r.cpu);
  const double lx0 = std::floor(std::log10(std::max(1e-3, smin))), lx1 = std::ceil(std::log10(std::max(smax, smin * 1.01)));
  for (int panel = 0; panel < 2; ++panel) {
    double emin = 1e30, emax = 0;
    auto err = [&](const Row& r) { return std::max(1e-5, panel == 0 ? r.toTruth : r.albedoErr); };
    for (const Row& r : rows) emin = std::min(emin, err(r)), emax = std::max(emax, err(r));
    const double ly0 = std::floor(std::log10(emin)), ly1 = std::ceil(std::log10(emax * 1.01));
    const int ox = left0 + panel * gap, oy = top + panelH;
    auto X = [&](double s) { return ox + static_cast<int>((std::log10(s) - lx0) / (lx1 - lx0) * panelW); };
    auto Y = [&](double e) { return oy - static_cast<int>((std::log10(e) - ly0) / (ly1 - ly0) * panelH); };
    cv::rectangle(img, cv::Point(ox, top), cv::Point(ox + panelW, oy), cv::Scalar(0, 0, 0), 1);
    for (double d = lx0; d <= lx1 + 1e-9; d += 1) {
      const int x = X(std::pow(10.0, d));
      cv::line(img, cv::Point(x, top), cv::Point(x, oy), cv::Scalar(220, 220, 220), 1);
      char b[32];
      std::snprintf(b, sizeof b, "%g", std::pow(10.0, d));
      cv::putText(img, b, cv::Point(x - 12, oy + 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    for (double d = ly0; d <= ly1 + 1e-9; d += 1) {
      const int y = Y(std::pow(10.0, d));
      cv::line(img, cv::Point(ox, y), cv::Point(ox + panelW, y), cv::Scalar(220, 220, 220), 1);
      char b[32];
      std::snprintf(b, sizeof b, "%g", std::pow(10.0, d));
      cv::putText(img, b, cv::Point(ox - 60, y + 5), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    cv::putText(img,
                panel == 0 ? "texture-feature distance to the truth"
                           : "mean-albedo error (max over channels)",
                cv::Point(ox + 60, top - 15), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0),
                1, cv::LINE_AA);
    cv::putText(img, "CPU seconds per part (one thread)", cv::Point(ox + 130, oy + 40), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    // one polyline per (graph, light, preset) through its budgets
    std::map<std::string, std::vector<cv::Point>> lines;
    for (const Row& r : rows) {
      const cv::Point p(X(r.cpu), Y(err(r)));
      const cv::Scalar col = palette[presetIdx[r.preset] % palette.size()];
      marker(p, graphIdx[r.graph], col);
      char key[256];
      std::snprintf(key, sizeof key, "%s/%g/%s", r.graph.c_str(), r.light, r.preset.c_str());
      lines[key].push_back(p);
    }
    for (auto& [key, pts] : lines) {
      const std::string preset = key.substr(key.rfind('/') + 1);
      if (pts.size() > 1) cv::polylines(img, pts, false, palette[presetIdx[preset] % palette.size()], 1, cv::LINE_AA);
    }
  }
  // legend
  int lx = left0, ly = H - 15;
  for (auto& [name, i] : presetIdx) {
    cv::circle(img, cv::Point(lx, ly - 4), 5, palette[i % palette.size()], -1, cv::LINE_AA);
    cv::putText(img, name, cv::Point(lx + 10, ly), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    lx += 100;
  }
  for (auto& [name, i] : graphIdx) {
    const cv::Point p(lx, ly - 4);
    marker(p, i, cv::Scalar(0, 0, 0));
    cv::putText(img, name, cv::Point(lx + 10, ly), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    lx += 20 + 10 * static_cast<int>(name.size());
  }
  cv::Mat rgb;  // drawn in OpenCV's BGR; ps::io writes RGB
  cv::cvtColor(img, rgb, cv::COLOR_BGR2RGB);
  io::writeRawImage(path, rgb);
}

// "--set key=value;key=value" overrides PartFitOptions fields after the preset.
void applyOverrides(PartFitOptions& o, const std::string& spec) {
  std::stringstream ss(spec);
  std::string kv;
  while (std::getline(ss, kv, ';')) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos) continue;
    const std::string k = kv.substr(0, eq);
    const double v = std::stod(kv.substr(eq + 1));
    const int i = static_cast<int>(v);
    if (k == "maxIterations") o.maxIterations = i;
    else if (k == "mapSize") o.mapSize = i;
    else if (k == "learningRate") o.learningRate = static_cast<float>(v);
    else if (k == "uvLearningRate") o.uvLearningRate = static_cast<float>(v);
    else if (k == "uvSearchEvery") o.uvSearchEvery = i;
    else if (k == "searchRotations") o.searchRotations = i;
    else if (k == "searchLogScales") o.searchLogScales = i;
    else if (k == "searchOffsets") o.searchOffsets = i;
    else if (k == "refineSteps") o.refineSteps = i;
    else if (k == "specularSub") o.specularSub = i;
    else if (k == "searchSpecularSub") o.searchSpecularSub = i;
    else if (k == "coarseLevels") o.coarseLevels = i;
    else if (k == "searchLevels") o.searchLevels = i;
    else if (k == "statWeight")
      o.statWeight = static_cast<float>(v);
    else if (k == "textureWeight")
      o.textureWeight = static_cast<float>(v);
    else if (k == "fineIterations") o.fineIterations = i;
    else if (k == "fineLearningRateScale") o.fineLearningRateScale = static_cast<float>(v);
    else if (k == "minLevelPixels") o.minLevelPixels = i;
    else if (k == "searchKeep") o.searchKeep = i;
    else if (k == "spectrumScaleWindow")
      o.spectrumScaleWindow = static_cast<float>(v);
    else if (k == "plateauWindow") o.plateau.window = i;
    else if (k == "plateauMinIterations") o.plateau.minIterations = i;
    else if (k == "plateauRel") o.plateau.minRelativeImprovement = v;
    else if (k == "placementWeight") o.placementWeight = static_cast<float>(v);
    else if (k == "placementSigma") o.placementSigma = static_cast<float>(v);
    else if (k == "placementOffsets") o.placementOffsets = i;
    else if (k == "psAutoLowpass") o.psAutoLowpass = static_cast<float>(v);
    else if (k == "psAutoMagnitude") o.psAutoMagnitude = static_cast<float>(v);
    else if (k == "psCrossOrientation") o.psCrossOrientation = static_cast<float>(v);
    else if (k == "psCrossScale") o.psCrossScale = static_cast<float>(v);
    else if (k == "psColor") o.psColor = static_cast<float>(v);
    else if (k == "colorSliced") o.colorSliced = static_cast<float>(v);
    else if (k == "bandShape") o.bandShape = static_cast<float>(v);
    else {
      std::fprintf(stderr, "--set: unknown option %s\n", k.c_str());
      std::exit(2);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> budgets = {0}, checkpoints;
  std::vector<float> lights = {12.0f, 30.0f};
  int W = 160, H = 120, threads = 1;
  std::string plotPath, csvPath, overrides, extraCsv;
  bool startTruth = false;
  std::string renderDir;
  std::string size = "160x120";
  CLI::App app{"Run time against error of the per-part material fit"};
  std::string presetList = "fast,balanced", graphList = "wood_planks,tile_checker";
  app.add_option("presets", presetList, "presets, comma-separated");
  app.add_option("graphs", graphList, "graphs, comma-separated");
  app.add_option("--iters", budgets, "iteration budgets, comma-separated (0: the preset's own)")
      ->delimiter(',');
  app.add_option("--checkpoints", checkpoints, "also a row at each of these Adam steps of one run")
      ->delimiter(',');
  app.add_option("--lights", lights, "light intensities, comma-separated")->delimiter(',');
  app.add_option("--size", size, "photo size WxH");
  app.add_option("--threads", threads, "threads (0: all)");
  app.add_option("--plot", plotPath, "error against seconds (PNG)");
  app.add_option("--csv", csvPath, "the table as CSV");
  app.add_option("--add-csv", extraCsv, "rows of an earlier CSV added to the plot");
  app.add_option("--set", overrides, "\"key=value;...\": PartFitOptions fields after the preset");
  app.add_option("--renders", renderDir, "write the photo and each fit's render (PNG)");
  app.add_flag("--start-truth", startTruth, "start from the true UV transform");
  CLI11_PARSE(app, argc, argv);
  if (std::sscanf(size.c_str(), "%dx%d", &W, &H) != 2) {
    std::fprintf(stderr, "--size: WxH expected, got %s\n", size.c_str());
    return 2;
  }
  const std::vector<std::string> presets = split(presetList);
  const std::vector<std::string> graphs = split(graphList);
  const ThreadLimit limit(threads);
  const GraphLibrary lib = GraphLibrary::load();
  std::vector<Row> rows;
  std::printf(
      "| graph | light | preset | budget | seconds | cpu | search s | iterations (coarse) | "
      "candidates | texture loss start -> end | at truth | yardstick | to truth | mean albedo err "
      "| rot err (deg, mod 180) | mod 90 | scale ratio | placement to truth |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& gname : graphs)
    for (float light : lights) {
      MaterialGraph truth = lib.create(gname);
      std::vector<float> v = truth.randomValues(21, 0.35f);
      const std::vector<float> d = truth.defaultValues();
      const std::vector<uint8_t> diff = truth.differentiableMask();
      for (size_t i = 0; i < v.size(); ++i)
        if (!diff[i]) v[i] = d[i];
      truth.setValues(v);
      UvParams uvTrue;
      uvTrue.rotation = radians(35.0f);
      uvTrue.logScale = std::log(0.35f);
      uvTrue.offset = Vec2f(0.1f, 0.3f);
      Room room = makeRoom(W, H, light);
      std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f), lambert("ceiling", 0.8f),
                                        lambert("box", 0.6f)};
      const MaterialMaps tm = truth.evaluate(256, MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
      PartMaterial& m = mats[room.floor];
      m.albedoMap = FloatTexture(tm.albedo);
      m.normalMap = FloatTexture(tm.normal);
      m.roughnessMap = FloatTexture(tm.roughness);
      m.specular = 0.5f;  // the layer's default: the truth is a dielectric with the graph's roughness map
      m.uv = uvTrue.toTransform();
      const PathTracer tracer(room.scene, mats);
      cv::Mat photo;
      testroom::View view;
      {
        const ThreadLimit all(0);  // the scene is set up with every core; only the fit is timed
        photo = tracer.render(room.camera, boxFilterOptions(256, 3));
        view = prepareView(tracer, room.camera, 8, 8, 9);
      }
      const PartGeometry geo = preparePartGeometry(view.gbuffer, room.camera.position().cast<float>(), view.grid,
                                                   view.gbuffer.mask[room.floor], room.floor);
      const TextureLossTarget target(photo, view.gbuffer.mask[room.floor]);
      std::fprintf(stderr, "%s light %g: %dx%d, part of %d pixels\n", gname.c_str(), light, W, H, geo.size());
      const std::string stem = renderDir + "/" + gname + "_" + std::to_string(static_cast<int>(light));
      if (!renderDir.empty()) io::writeImage(stem + "_photo.png", photo);
      // the truth rendered noise-free with the yardstick's settings, and its texture-loss target
      const cv::Mat& mask = view.gbuffer.mask[room.floor];
      auto renderAt = [&](const MaterialMaps& mm, const cv::Mat& roughness, const UvParams& uv) {
        RenderLayerParams p;
        p.geometry = &geo;
        p.albedo = mm.albedo;
        p.normal = mm.normal;
        p.roughness = roughness;
        p.uv = uv;
        p.specularSub = 2;
        renderLayerForward(p);
        return p.image;
      };
      auto textureDistance = [](const TextureLossTarget& t, const cv::Mat& render) {
        TextureLossParams tp;
        tp.target = &t;
        tp.render = render;
        return textureLossForward(tp);
      };
      const cv::Mat truthRender = renderAt(tm, tm.roughness, uvTrue);
      const TextureLossTarget truthTarget(truthRender, mask);
      // where the pattern lies against the truth (UV offset and rotation of seams and grout): the
      // placement term between the noise-free renders, sigma 2 pixels
      const PlacementLossTarget truthPlacement(truthRender, mask, PlacementLossOptions{2.0});
      const double truthYardstick = textureDistance(target, truthRender);
      // one row's errors from a fitted state (values, transform, mean roughness)
      auto measure = [&](Row& row, const std::vector<float>& values, const UvParams& uv,
                         float roughness) {
        MaterialGraph fitted = lib.create(gname);
        fitted.setValues(values);
        const MaterialMaps fm = fitted.evaluate(
            256, MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
        cv::Mat rough = fm.roughness.clone();
        const double mr = cv::mean(rough)[0];
        if (mr > 1e-4)
          rough *= roughness / mr;
        else
          rough.setTo(roughness);
        const cv::Mat render = renderAt(fm, rough, uv);
        row.yardstick = textureDistance(target, render);
        row.toTruth = textureDistance(truthTarget, render);
        row.placement = placementLoss(truthPlacement, render);
        const cv::Scalar mf = cv::mean(fm.albedo), mt = cv::mean(tm.albedo);
        row.albedoErr =
            std::max({std::abs(mf[0] - mt[0]), std::abs(mf[1] - mt[1]), std::abs(mf[2] - mt[2])});
        const cv::Scalar rf = cv::mean(render, mask), rt = cv::mean(truthRender, mask), ph = cv::mean(photo, mask);
        std::fprintf(stderr,
                     "  step %d: mean albedo (%.3f %.3f %.3f), truth (%.3f %.3f %.3f); masked render mean "
                     "(%.3f %.3f %.3f), truth's (%.3f %.3f %.3f), photo (%.3f %.3f %.3f); roughness %.3f, "
                     "truth %.3f\n",
                     row.iterations, mf[0], mf[1], mf[2], mt[0], mt[1], mt[2], rf[0], rf[1], rf[2], rt[0], rt[1],
                     rt[2], ph[0], ph[1], ph[2], roughness, cv::mean(tm.roughness)[0]);
        double rot = degrees(uv.rotation - uvTrue.rotation);
        rot = std::fmod(std::fmod(rot, 180.0) + 270.0, 180.0) - 90.0;
        row.rot = rot;
        row.rot90 = std::fmod(std::fmod(rot, 90.0) + 135.0, 90.0) - 45.0;  // square tiles
        row.scale = std::exp(uv.logScale - uvTrue.logScale);
      };
      auto print = [&](const Row& row, double searchSeconds, int coarse) {
        std::printf(
            "| %s | %.0f | %s | %d | %.2f | %.2f | %.2f | %d (%d) | %d | %.4f -> %.4f | %.4f | "
            "%.4f | %.4f | %.3f | %.1f | %.1f | %.3f | %.3f |\n",
            row.graph.c_str(), row.light, row.preset.c_str(), row.budget, row.seconds, row.cpu,
            searchSeconds, row.iterations, coarse, row.candidates, row.texStart, row.texEnd,
            row.atTruth, row.yardstick, row.toTruth, row.albedoErr, row.rot, row.rot90, row.scale,
            row.placement);
        std::fflush(stdout);
      };
      for (const std::string& preset : presets)
        for (int budget : budgets) {
          PartFitOptions o = PartFitOptions::preset(preset);
          applyOverrides(o, overrides);
          if (budget > 0) o.maxIterations = budget;
          PartFitOptions z = o;
          z.maxIterations = 0;
          const PartFitResult atTruth = fitPart(truth, geo, photo, target, z, uvTrue);
          Row row;
          row.graph = gname;
          row.preset = preset;
          row.light = light;
          row.texStart = std::nan("");  // known after the fit
          row.atTruth = atTruth.initialTextureLoss;
          // checkpoints: the best state so far at the listed steps, measured and printed at once
          // (a long run can be stopped); the measuring time is left out of the times
          const Timer wall;
          const std::clock_t c0 = std::clock();
          double pausedWall = 0;
          std::clock_t pausedCpu = 0;
          o.onProgress = [&](const PartFitProgress& pr) {
            if (pr.phase != PartFitProgress::Phase::Step ||
                std::find(checkpoints.begin(), checkpoints.end(), pr.iteration) == checkpoints.end())
              return true;
            const Timer pause;
            const std::clock_t p0 = std::clock();
            Row c = row;
            c.budget = c.iterations = pr.iteration;
            c.seconds = wall.seconds() - pausedWall;
            c.cpu = static_cast<double>(std::clock() - c0 - pausedCpu) / CLOCKS_PER_SEC;
            c.texEnd = std::nan("");
            measure(c, pr.values, pr.uv, pr.roughness);
            rows.push_back(c);
            print(c, std::nan(""), 0);
            pausedWall += pause.seconds();
            pausedCpu += std::clock() - p0;
            return true;
          };
          const PartFitResult r =
              fitPart(lib.get(gname), geo, photo, target, o, startTruth ? uvTrue : UvParams{});
          const double cpu = static_cast<double>(std::clock() - c0 - pausedCpu) / CLOCKS_PER_SEC;
          if (!renderDir.empty())
            io::writeImage(stem + "_" + preset + "_" + std::to_string(o.maxIterations) + ".png", r.render);
          row.texStart = r.initialTextureLoss;
          row.budget = o.maxIterations;
          row.seconds = r.seconds - pausedWall;
          row.cpu = cpu;
          row.iterations = r.iterations;
          row.candidates = r.candidates;
          row.texEnd = r.lossTexture;
          measure(row, r.values, r.uv, r.roughness);
          rows.push_back(row);
          print(row, r.searchSeconds, r.coarseIterations);
          std::fprintf(stderr, "  truth: yardstick %.5f (its distance to the photo's noise)\n",
                       truthYardstick);
          std::fprintf(stderr,
                       "  spectral prior (%.3f s): ok %d, response %.3f, scale ratio %.3f, "
                       "rotation %.1f deg mod 180\n",
                       r.spectrumSeconds, r.spectrum.ok, r.spectrum.response,
                       std::exp(r.spectrum.logScale - uvTrue.logScale),
                       degrees(r.spectrum.rotation));
        }
    }
  if (!csvPath.empty()) {
    if (FILE* f = std::fopen(csvPath.c_str(), "w")) {
      std::fprintf(f,
                   "graph,light,preset,budget,seconds,cpu,iterations,candidates,tex_start,tex_end,"
                   "at_truth,albedo_err,rot,rot90,scale,yardstick,to_truth,placement\n");
      for (const Row& r : rows)
        std::fprintf(f,
                     "%s,%g,%s,%d,%.3f,%.3f,%d,%d,%.5f,%.5f,%.5f,%.4f,%.2f,%.2f,%.4f,%.5f,%.5f,"
                     "%.4f\n",
                     r.graph.c_str(), r.light, r.preset.c_str(), r.budget, r.seconds, r.cpu,
                     r.iterations, r.candidates, r.texStart, r.texEnd, r.atTruth, r.albedoErr,
                     r.rot, r.rot90, r.scale, r.yardstick, r.toTruth, r.placement);
      std::fclose(f);
    }
  }
  if (!extraCsv.empty()) {
    // rows of an earlier run (e.g. the slow `paper` preset on one case) drawn in the same plot
    if (FILE* f = std::fopen(extraCsv.c_str(), "r")) {
      char line[1024];
      bool header = true;
      while (std::fgets(line, sizeof line, f)) {
        if (header) {
          header = false;
          continue;
        }
        const std::vector<std::string> v = split(std::string(line));
        if (v.size() < 17) continue;  // older files have no errors against the truth
        Row r;
        r.graph = v[0];
        r.light = std::stof(v[1]);
        r.preset = v[2];
        r.budget = std::stoi(v[3]);
        r.seconds = std::stod(v[4]);
        r.cpu = std::stod(v[5]);
        r.iterations = std::stoi(v[6]);
        r.candidates = std::stoi(v[7]);
        r.texStart = std::stod(v[8]);
        r.texEnd = std::stod(v[9]);
        r.atTruth = std::stod(v[10]);
        r.albedoErr = std::stod(v[11]);
        r.rot = std::stod(v[12]);
        r.rot90 = std::stod(v[13]);
        r.scale = std::stod(v[14]);
        r.yardstick = std::stod(v[15]);
        r.toTruth = std::stod(v[16]);
        rows.push_back(r);
      }
      std::fclose(f);
    }
  }
  if (!plotPath.empty()) plot(rows, plotPath);
  return 0;
}
