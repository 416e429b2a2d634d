// What the fit's loss says of the true material (issue 17): on the real-texture yardstick's cases,
// with everything but the loss made perfect, does the photographed material itself beat a flat
// colour by the margin that selection asks of a graph?
//
//   ps_bench_loss_oracle --work WORK [--data ../shared/data] [--split tune|check|all]
//                        [--lighting warm] [--preset fast] [--limit N] [--offsets 4]
//                        [--materials A,B] [--csv FILE]
//
// Reads the case folders that ps_bench_real_textures wrote under WORK/scenes (it generates none).
// Per case and textured part, in view 0: the true twin's G-buffer and incident-light grid (true
// geometry, lights and materials; the grid as the pipeline's `fast` or `balanced` incident0 traces
// it), the part's true label mask eroded by one pixel, the photo (photos/view0.png). Then, by the
// fit's own loss (optim's scoreMaps / PartFitOptions::preset):
//   flat   the homogeneous finalist as selection scores it (select's homogeneousPartFit)
//   true   the photographed maps at the true UV transform (pixel-aligned)
//   offset the photographed maps at `--offsets` random UV offsets (the right texture, not aligned:
//          what a fitted graph can at best reach), the mean loss
// and the model-selection tests of select (TextureEvidence) on the offset renders. A part where
// `offset` does not beat `flat` by the margin cannot get a texture from selection, whatever the
// library holds: the loss, not the graphs, is what stands in the way there.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/optim.hpp"
#include "photoscene/pipeline/pipeline.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"
#include "photoscene/select.hpp"
#include "real_materials.hpp"

namespace fs = std::filesystem;
using namespace ps;

namespace {

constexpr int kSkipCode = 77;

using bench::fnv1a;
using bench::splitOf;

MaterialMaps trueMaps(const bench::RealMaterial& m, int size) {
  MaterialMaps maps;
  cv::resize(io::readImage(m.albedo), maps.albedo, {size, size}, 0, 0, cv::INTER_AREA);
  maps.normal = m.normal.empty() ? cv::Mat(size, size, CV_32FC3, cv::Scalar(0, 0, 1))
                                 : bench::loadNormalMap(m.normal, m.normalDirectX, size);
  return maps;
}

/// Per pyramid level, the orientation mean of the band energy (meanMag) over the part, divided by
/// the photo's mean luminance nu: where the texture loss sees energy.
std::string bandEnergies(const cv::Mat& image, const cv::Mat& mask, double nu) {
  const TextureDescriptorOptions o;
  const TextureDescriptor d = computeTextureDescriptor(image, mask, o);
  std::string out;
  for (int sc = 0; sc < o.numScales; ++sc) {
    double e = 0;
    for (int k = 0; k < o.numOrientations; ++k) e += d.values[bandIndex(o, sc, k) + kBandMeanMag];
    out += fmt::format(" {:.4f}", e / o.numOrientations / nu);
  }
  return out;
}

/// photo | flat | true side by side over the part's bounding box, sRGB, zero outside the mask
void writeCrops(const fs::path& file, const cv::Mat& mask, const std::vector<cv::Mat>& images) {
  const cv::Rect box = cv::boundingRect(mask);
  std::vector<cv::Mat> crops;
  for (const cv::Mat& im : images) {
    cv::Mat c = cv::Mat::zeros(box.size(), CV_32FC3);
    im(box).copyTo(c, mask(box));
    crops.push_back(c);
  }
  cv::Mat row;
  cv::hconcat(crops, row);
  fs::create_directories(file.parent_path());
  io::writeImage(file, row);
}

struct Row {
  std::string material, split, category, part;
  int pixels = 0;
  PartFitResult flat, aligned;
  double flatLoss = 0;  ///< lossData of flat
  double offsetLoss = 0, offsetStat = 0, offsetTex = 0;
  int offsetPass = 0;  ///< offsets whose render passes select's texture tests
  /// the same offsets with the render's channel means scaled to the photo's first (a graph's
  /// albedo offset fits the mean, the homogeneous finalist's in closed form; the true maps under
  /// the traced grid miss it by the grid's noise and the photo's clipping)
  double matchedLoss = 0, matchedStat = 0, matchedTex = 0;
};

}  // namespace

int main(int argc, char** argv) {
  fs::path data = "../shared/data", work = "build/real-textures";
  std::string split = "all", lighting = "warm", preset = "fast", csv, materialList;
  int limit = 0, offsets = 4, threads = 2, mapSize = 256;
  CLI::App app{"What the fit's loss says of the true material on the real-texture yardstick"};
  app.add_option("--data", data, "the shared data folder");
  app.add_option("--work", work, "ps_bench_real_textures' work folder (its scenes/)");
  app.add_option("--split", split, "tune, check or all")->check(CLI::IsMember({"tune", "check", "all"}));
  app.add_option("--lighting", lighting, "warm or window");
  app.add_option("--preset", preset, "fit options and incident grid of this preset")
      ->check(CLI::IsMember({"fast", "balanced", "paper"}));
  app.add_option("--limit", limit, "at most this many materials (0: all)");
  app.add_option("--materials", materialList, "only these materials (comma-separated)");
  app.add_option("--offsets", offsets, "random UV offsets of the true maps")->check(CLI::Range(1, 64));
  app.add_option("--map-size", mapSize, "the true maps resampled to this size (power of two)");
  app.add_option("--threads", threads, "worker threads");
  app.add_option("--csv", csv, "write the rows here");
  int gridSamples = 0, gridStride = 0, gridDirect = -1;
  app.add_option("--grid-samples", gridSamples, "incident grid: path samples per bin (0: the preset's)");
  app.add_option("--grid-stride", gridStride, "incident grid: pixels between points (0: the preset's)");
  app.add_option("--grid-direct", gridDirect, "incident grid: light samples per point (-1: the preset's 0)");
  float lobeFilter = 0;
  app.add_option("--lobe-filter", lobeFilter, "the render layer's lobe filter (RenderLayerParams)")
      ->check(CLI::Range(0.0f, 4.0f));
  fs::path dump;
  app.add_option("--dump", dump, "write photo | flat | true (aligned) crops of each part here");
  bool bands = false;
  app.add_flag("--bands", bands, "print each level's band energy of photo, flat and true renders");
  CLI11_PARSE(app, argc, argv);
  if (!fs::exists(data / "textures/cc0/manifest.json")) {
    std::fprintf(stderr, "no shared data at %s: skipped\n", data.string().c_str());
    return kSkipCode;
  }
  ThreadLimit threadLimit(threads > 0 ? threads : 0);
  std::map<std::string, bench::RealMaterial> byName;
  for (const bench::RealMaterial& m : bench::listRealMaterials(data)) byName[m.name] = m;
  std::vector<std::string> only;
  for (size_t a = 0; !materialList.empty() && a != std::string::npos;) {
    const size_t b = materialList.find(',', a);
    only.push_back(materialList.substr(a, b == std::string::npos ? b : b - a));
    a = b == std::string::npos ? b : b + 1;
  }

  const GraphLibrary library = GraphLibrary::load();
  PartFitOptions fo = PartFitOptions::preset(preset);
  fo.lobeFilter = lobeFilter;
  const SynthesisOptions so = synthesisPreset(preset);
  // the pipeline's incident0 grid for the preset (run_options.cpp's PresetBudget)
  IncidentLightOptions io;
  io.stride = preset == "paper" ? 4 : 8;
  io.samplesPerBin = preset == "fast" ? 4 : preset == "paper" ? 16 : 8;
  io.directSamples = 0;
  if (gridSamples > 0) io.samplesPerBin = gridSamples;
  if (gridStride > 0) io.stride = gridStride;
  if (gridDirect >= 0) io.directSamples = gridDirect;

  std::vector<Row> rows;
  int cases = 0;
  for (const auto& [name, mat] : byName) {
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
    if (split != "all" && splitOf(name) != split) continue;
    const fs::path dir = work / "scenes" / name / lighting;
    if (!fs::exists(dir / "scene.json")) continue;
    if (limit > 0 && cases >= limit) break;
    ++cases;
    const Twin twin = loadTwin(dir / "gt/twin");
    const nlohmann::json truth = io::readJsonFile(dir / "gt/truth.json");
    const cv::Mat photo = io::readImage(dir / "photos/view0.png");
    const Camera& cam = twin.scene.views[0].camera;
    const PathTracer tracer(twin.scene, twin.materials);
    const GBuffer gb = renderGBuffer(tracer, cam);
    io.render.seed = 101;
    const IncidentLightGrid grid = computeIncidentLight(tracer, gb, cam, io);
    const MaterialMaps maps = trueMaps(mat, mapSize);
    const float roughness =
        mat.roughness.empty() ? 0.6f
                              : static_cast<float>(cv::mean(io::readDataImage(mat.roughness))[0]);
    for (const auto& [part, t] : truth.at("parts").items()) {
      int id = -1;
      for (const Part& p : twin.scene.parts)
        if (p.name == part) id = p.id;
      if (id < 0) continue;
      cv::Mat mask = gb.partId == id;
      cv::erode(mask, mask, cv::Mat());
      if (cv::countNonZero(mask) < 64) continue;
      const PartGeometry geo =
          preparePartGeometry(gb, cam.position().cast<float>(), grid, mask, id);
      const TextureLossTarget target(photo, mask);
      Row r;
      r.material = name;
      r.split = splitOf(name);
      r.category = mat.category;
      r.part = part;
      r.pixels = geo.size();
      r.flat = homogeneousPartFit(library, geo, photo, target, fo);
      r.flatLoss = r.flat.lossData;
      const UvParams uv = UvParams::fromTransform(twin.materials[id].uv);
      r.aligned = scoreMaps(maps, mat.category, uv, roughness, geo, photo, target, fo);
      if (!dump.empty()) writeCrops(dump / (name + "_" + part + ".png"), mask,
                                    {photo, r.flat.render, r.aligned.render});
      Rng rng(fnv1a(name + part));
      for (int k = 0; k < offsets; ++k) {
        UvParams moved = uv;
        moved.offset += Vec2f(rng.uniform(), rng.uniform());
        const PartFitResult s = scoreMaps(maps, mat.category, moved, roughness, geo, photo, target, fo);
        r.offsetLoss += s.lossData / offsets;
        r.offsetStat += s.lossStat / offsets;
        r.offsetTex += s.lossTexture / offsets;
        if (bands && k == 0) {
        const double nu = target.normalizer();
        const PartFitResult m0 =
            scoreMaps(maps, mat.category, moved, roughness, geo, photo, target, fo, true);
        std::printf("  bands %-11s photo%s | flat%s | true off-register%s\n", part.c_str(),
                    bandEnergies(photo, mask, nu).c_str(),
                    bandEnergies(r.flat.render, mask, nu).c_str(),
                    bandEnergies(m0.render, mask, nu).c_str());
      }
      r.offsetPass += textureEvidence(s.render, r.flat.render, photo, geo, so).ok();
        const PartFitResult m =
            scoreMaps(maps, mat.category, moved, roughness, geo, photo, target, fo, true);
        r.matchedLoss += m.lossData / offsets;
        r.matchedStat += m.lossStat / offsets;
        r.matchedTex += m.lossTexture / offsets;
      }
      rows.push_back(r);
      std::printf(
          "%-36s %-5s %-8s %-11s %6d  flat %.4f (stat %.4f tex %.4f)  true %.4f (%.4f %.4f)  "
          "offset %.4f (%.4f %.4f)  means matched %.4f (%.4f %.4f)  ratio %.2f / %.2f  tests %d/%d\n",
          name.c_str(), r.split.c_str(), r.category.c_str(), part.c_str(), r.pixels, r.flatLoss,
          r.flat.lossStat, r.flat.lossTexture, r.aligned.lossData, r.aligned.lossStat,
          r.aligned.lossTexture, r.offsetLoss, r.offsetStat, r.offsetTex, r.matchedLoss,
          r.matchedStat, r.matchedTex, r.offsetLoss / std::max(1e-12, r.flatLoss),
          r.matchedLoss / std::max(1e-12, r.flatLoss), r.offsetPass, offsets);
      std::fflush(stdout);
    }
  }
  if (rows.empty()) {
    std::fprintf(stderr, "no case folders under %s/scenes (run ps_bench_real_textures first)\n",
                 work.string().c_str());
    return 1;
  }
  for (const std::string& half : {std::string("tune"), std::string("check")}) {
    int n = 0, large = 0, beats = 0, beatsLarge = 0, passLarge = 0, matchedLarge = 0;
    for (const Row& r : rows) {
      if (r.split != half) continue;
      const bool b = r.offsetLoss < (1 - so.textureMargin) * r.flatLoss;
      ++n;
      beats += b;
      if (r.pixels >= 2000) {
        ++large;
        beatsLarge += b;
        passLarge += b && 2 * r.offsetPass >= offsets;
        matchedLarge += r.matchedLoss < (1 - so.textureMargin) * r.flatLoss;
      }
    }
    if (n == 0) continue;
    std::printf(
        "%s: the true material off-register beats the flat colour by the %.0f %% margin on %d of "
        "%d parts (%d of %d parts >= 2000 px; %d of those also pass the texture tests); with the "
        "means matched on %d of the %d\n",
        half.c_str(), 100 * so.textureMargin, beats, n, beatsLarge, large, passLarge,
        matchedLarge, large);
  }
  if (!csv.empty()) {
    std::ofstream f(csv);
    f << "material,split,category,part,pixels,flat,flat_stat,flat_tex,true,true_stat,true_tex,"
         "offset,offset_stat,offset_tex,offset_pass,matched,matched_stat,matched_tex\n";
    for (const Row& r : rows)
      f << r.material << ',' << r.split << ',' << r.category << ',' << r.part << ',' << r.pixels
        << ',' << r.flatLoss << ',' << r.flat.lossStat << ',' << r.flat.lossTexture << ','
        << r.aligned.lossData << ',' << r.aligned.lossStat << ',' << r.aligned.lossTexture << ','
        << r.offsetLoss << ',' << r.offsetStat << ',' << r.offsetTex << ',' << r.offsetPass
        << '\n';
  }
  return 0;
}
