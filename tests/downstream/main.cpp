// A downstream program of an installed photoscene: loads the material-graph library (found by
// the installed tree itself), renders a library graph with perturbed parameters onto a flat part
// under a sky of light (render layer), and fits the graph's defaults back to that image with the
// per-part fit (optim). Exit 0 only when every check holds.
//
//   fit_part [expected graph folder]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <photoscene/core.hpp>
#include <photoscene/graph.hpp>
#include <photoscene/optim.hpp>
#include <photoscene/render.hpp>

namespace {

int failures = 0;
void check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what.c_str());
    ++failures;
  }
}

bool finiteIn(const cv::Mat& m, float lo, float hi) {
  cv::Mat f = m.reshape(1);
  for (int y = 0; y < f.rows; ++y)
    for (int x = 0; x < f.cols; ++x) {
      const float v = f.at<float>(y, x);
      if (!std::isfinite(v) || v < lo || v > hi) return false;
    }
  return true;
}

// An n x n pixel square of floor seen from above, uv over [0, 1)^2, lit by a uniform sky.
ps::PartGeometry flatPart(int n) {
  ps::PartGeometry g;
  g.imageSize = cv::Size(n, n);
  g.part = 0;
  g.thetaBins = 4;
  g.phiBins = 8;
  g.bins = g.thetaBins * g.phiBins;
  g.binSolidAngle = 2 * ps::kPi / g.bins;
  for (int i = 0; i < g.thetaBins; ++i)
    for (int j = 0; j < g.phiBins; ++j) {
      const float cosT = 1.0f - (i + 0.5f) / g.thetaBins,
                  phi = 2 * ps::kPi * (j + 0.5f) / g.phiBins;
      const float sinT = std::sqrt(1 - cosT * cosT);
      g.binDir.emplace_back(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      g.pixels.emplace_back(x, y);
      ps::PartGeometry::Pixel px;
      px.uv = ps::Vec2f((x + 0.5f) / n, 1.0f - (y + 0.5f) / n);
      px.footprint = 1.0f / n;
      g.data.push_back(px);
    }
  g.light.assign(static_cast<size_t>(g.size()) * g.bins * 3, 1.0f);
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    ps::setLogLevel(ps::LogLevel::Warn);
    const ps::GraphLibrary lib = ps::GraphLibrary::load();
    std::printf("graph library: %s (%d graphs)\n", lib.folder().c_str(), lib.size());
    check(lib.size() > 0, "the library has graphs");
    if (argc > 1)
      check(std::filesystem::equivalent(lib.folder(), argv[1]),
            "the library is the installed one (" + std::string(argv[1]) + ")");
    const std::string name = "brick_red";
    check(lib.contains(name), "the library has " + name);

    // graph: the truth's maps
    ps::MaterialGraph truth = lib.create(name);
    truth.setValues(truth.randomValues(7, 0.3f));
    const ps::MaterialMaps maps = truth.evaluate(32);
    check(finiteIn(maps.albedo, 0, 1), "albedo finite in [0, 1]");
    check(finiteIn(maps.roughness, 0, 1), "roughness finite in [0, 1]");
    check(finiteIn(maps.normal, -1, 1), "normal finite in [-1, 1]");

    // render: the "photo" of the part
    const int n = 24;
    const ps::PartGeometry geo = flatPart(n);
    ps::RenderLayerParams p;
    p.geometry = &geo;
    p.albedo = maps.albedo;
    p.normal = maps.normal;
    p.roughness = maps.roughness;
    ps::renderLayerForward(p);
    const cv::Mat photo = p.image.clone();
    // a white Lambertian surface under unit radiance would be 1; albedo <= 1 plus a specular lobe
    check(photo.size() == cv::Size(n, n) && finiteIn(photo, 0, 2), "render finite in [0, 2]");
    check(cv::mean(photo)[0] > 0.01, "render not black");

    // optim: fit the graph's defaults to the photo
    const cv::Mat mask(n, n, CV_8UC1, cv::Scalar(255));
    const ps::TextureLossTarget target(photo, mask);
    ps::PartFitOptions o = ps::PartFitOptions::preset("fast");
    o.maxIterations = 15;
    o.mapSize = 32;
    o.coarseLevels = 0;
    o.searchLevels = 0;
    o.searchRotations = 4;
    o.searchLogScales = 3;
    o.refineSteps = 0;
    o.spectrumScaleWindow = 0;
    std::string err;
    check(o.IsValid(&err), "fit options valid: " + err);
    const ps::PartFitResult r = ps::fitPart(lib.get(name), geo, photo, target, o);
    std::printf("fit %s: loss %.5f -> %.5f in %d steps (%.2f s)\n", name.c_str(), r.initialLoss,
                r.loss, r.iterations, r.seconds);
    check(std::isfinite(r.loss) && std::isfinite(r.initialLoss), "losses finite");
    check(r.iterations > 0, "Adam steps taken");
    check(r.loss < r.initialLoss, "the fit lowers the loss");
    bool valuesFinite = true;
    for (float v : r.values) valuesFinite &= std::isfinite(v);
    check(valuesFinite && r.values.size() == truth.values().size(), "fitted values finite");
    check(finiteIn(r.render, 0, 2), "fitted render finite in [0, 2]");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAILED: %s\n", e.what());
    return 1;
  }
  if (failures) return 1;
  std::printf("ok\n");
  return 0;
}
