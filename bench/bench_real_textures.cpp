// The real-texture yardstick (issue 17): photographed CC0 materials on the parts of a small room,
// path-traced by the project's own renderer, run through the pipeline, scored per part.
//
//   ps_bench_real_textures [--data ../shared/data] [--work build/real-textures]
//                          [--materials NAME,NAME] [--limit N] [--split all|tune|check]
//                          [--lightings warm,window] [--preset fast] [--threads 2]
//                          [--width 320 --height 240] [--spp 32] [--texture-size 64]
//                          [--csv FILE] [--sheet FILE.png] [--sheet-rows 12] [--check]
//
// Per material (textures/cc0/manifest.json, plus the three maps of textures/polyhaven/), and per
// lighting, the generator writes a case folder WORK/scenes/<material>/<lighting>/ in the contract's
// format (regenerated only when missing):
//   room.obj        a 4 x 2.6 x 3.5 m room: `floor`, `wall` (the back wall), a low box whose top is
//                   `box_top`, an ottoman whose five visible faces are `upholstered` (these four
//                   parts wear the material), neutral `walls`, `ceiling`, `box_side` (given as
//                   `fixed` in scene.json, as a user would give a wall colour), and for the window
//                   lighting a 2.8 x 1.6 m `window` opening in the left wall. UVs in meters (planar
//                   per face).
//   lightings       warm: one 0.8 x 0.5 m ceiling rectangle of warm radiance (2900 K-ish);
//                   window: the window part with the environment blender-room/env/forest.exr
//                   behind it, nothing else. Intensities are to be fitted (not given).
//   photos          view0, view1 from two cameras, path-traced at --spp (2 x --spp for the window
//                   lighting, whose light converges slower; the pipeline renders at the same spp),
//                   exposed so that the 90th percentile luminance is 0.8, sRGB 8-bit
//   segments        16-bit labels 1000 + part id from the G-buffer, pinned by segment_parts
//   gt/twin         the true twin (materials/<part>.json with the photographed maps)
//   gt/offset_view<i>.exr   the true twin with every textured part's UV offset moved by a random
//                   amount (right texture, not pixel-aligned), rendered from view i with another
//                   seed: the texture distance this reaches is the bar the fit is held to.
// The runner calls ps::runPipeline twice per case (the method at --preset, and
// Baseline::PixelMedian) into WORK/runs/<material>/<lighting>/{method,pixel-median}, then scores
// every part in every view (its true label mask eroded by one pixel): masked RMSE in sRGB 0-255
// of the fitted render and of the baseline's render against the photo, the texture distance
// (ps::eval::textureDistance, not part of any loss) of the fitted render and of the offset truth
// against the photo; chosen graph and category, the top-5 kNN candidates with their vote shares
// (materials/<part>.json fit.candidates), pixels, seconds per stage. Results are cached per case
// in WORK/results/<material>_<lighting>.json.
//
// Split: a material is in `tune` when the FNV-1a 64-bit hash of its name is even, else `check`.
// Tune only on `tune`; the `check` numbers are the ones that count.
//
// --check (the ctest): exits 1 unless every case ran and every part of every case has a finite
// RMSE, distance and time; exits 77 (ctest's skip code) when the data folder is absent.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/eval.hpp"
#include "photoscene/io.hpp"
#include "photoscene/pipeline/pipeline.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"
#include "photoscene/select.hpp"
#include "photoscene/core/color.hpp"
#include "real_materials.hpp"
#include "../samples/tools/synthetic_obj.hpp"

namespace fs = std::filesystem;
using namespace ps;

namespace {

constexpr int kSkipCode = 77;
const std::vector<std::string> kTexturedParts = {"floor", "wall", "box_top", "upholstered"};
constexpr int kCategoryMinPixels = 2000;

// ---------------------------------------------------------------- materials

using bench::RealMaterial;

using bench::fnv1a;
using bench::splitOf;

// ---------------------------------------------------------------- geometry

struct Quad {
  std::string part;
  Vec3f a, b, c, d;  ///< counter-clockwise seen from the side the face shows
};

/// Axis-aligned box faces seen from outside (the bottom face left out), as quads.
std::vector<Quad> boxQuads(const Vec3f& l, const Vec3f& h, const std::string& top,
                           const std::string& sides) {
  const Vec3f c[8] = {{l.x(), l.y(), l.z()}, {h.x(), l.y(), l.z()}, {h.x(), h.y(), l.z()},
                      {l.x(), h.y(), l.z()}, {l.x(), l.y(), h.z()}, {h.x(), l.y(), h.z()},
                      {h.x(), h.y(), h.z()}, {l.x(), h.y(), h.z()}};
  return {{sides, c[0], c[3], c[2], c[1]},
          {sides, c[4], c[5], c[6], c[7]},
          {sides, c[0], c[4], c[7], c[3]},
          {sides, c[1], c[2], c[6], c[5]},
          {top, c[3], c[7], c[6], c[2]}};
}

/// The room (see the file comment); `room20`: the 20-part variant of the timing case, where the
/// side walls wear materials too and eight boxes replace the box and the ottoman, each with a
/// `top_<k>` and a `side_<k>` part.
io::ObjMesh roomMesh(bool window, bool room20) {
  const float X = 2.0f, H = 2.6f, Z = 1.75f;
  std::vector<Quad> q;
  // seen from inside
  q.push_back({"floor", {-X, 0, -Z}, {-X, 0, Z}, {X, 0, Z}, {X, 0, -Z}});
  q.push_back({"ceiling", {-X, H, -Z}, {X, H, -Z}, {X, H, Z}, {-X, H, Z}});
  q.push_back({"wall", {-X, 0, -Z}, {X, 0, -Z}, {X, H, -Z}, {-X, H, -Z}});
  q.push_back({"walls", {X, 0, Z}, {-X, 0, Z}, {-X, H, Z}, {X, H, Z}});
  q.push_back({room20 ? "wall_right" : "walls", {X, 0, -Z}, {X, 0, Z}, {X, H, Z}, {X, H, -Z}});
  // left wall (x = -X, seen from +x) around a window opening z in [-0.7, 0.5], y in [0.9, 2.0]
  const float z0 = -1.5f, z1 = 1.3f, y0 = 0.8f, y1 = 2.4f;
  auto left = [&](const std::string& part, float za, float zb, float ya, float yb) {
    q.push_back({part, {-X, ya, za}, {-X, ya, zb}, {-X, yb, zb}, {-X, yb, za}});
  };
  const std::string leftPart = room20 ? "wall_left" : "walls";
  left(leftPart, -Z, z0, 0, H);
  left(leftPart, z1, Z, 0, H);
  left(leftPart, z0, z1, 0, y0);
  left(leftPart, z0, z1, y1, H);
  left(window ? "window" : leftPart, z0, z1, y0, y1);
  if (room20) {
    for (int k = 0; k < 8; ++k) {
      const float x = -1.7f + 0.85f * (k % 4), z = -1.45f + 0.9f * (k / 4),
                  h = 0.3f + 0.08f * (k % 3);
      for (const Quad& b : boxQuads({x, 0, z}, {x + 0.6f, h, z + 0.55f}, fmt::format("top_{}", k),
                                    fmt::format("side_{}", k)))
        q.push_back(b);
    }
  } else {
    for (const Quad& b : boxQuads({-0.9f, 0, -1.1f}, {0.2f, 0.5f, -0.35f}, "box_top", "box_side"))
      q.push_back(b);
    for (const Quad& b :
         boxQuads({0.55f, 0, -0.55f}, {1.35f, 0.45f, 0.25f}, "upholstered", "upholstered"))
      q.push_back(b);
  }
  io::ObjMesh m;
  for (const Quad& f : q) {
    const int mat = tools::materialIndex(m, f.part);
    tools::addQuad(m, {f.a, f.b, f.c, f.d}, mat);
  }
  return m;
}

struct CaseGeometry {
  io::CameraDesc cams[2];
};

CaseGeometry cameras(int w, int h) {
  CaseGeometry g;
  g.cams[0] = io::lookAtCamera(w, h, 62, Vec3d(-1.3, 1.55, 1.55), Vec3d(0.1, 0.45, -1.0));
  g.cams[1] = io::lookAtCamera(w, h, 62, Vec3d(1.6, 1.45, 1.5), Vec3d(-0.2, 0.45, -1.0));
  return g;
}

/// Map period in meters per textured part (the material's own size when the manifest has it).
double periodFor(const RealMaterial& m, const std::string& part) {
  const double base = m.sizeM > 0 ? m.sizeM : 1.5;
  if (part == "box_top" || part.rfind("top_", 0) == 0) return base * 0.55;
  if (part == "upholstered" || part.rfind("side_", 0) == 0) return base * 0.4;
  return base;
}

/// One case: which material each textured part wears.
struct CaseSpec {
  std::string name;  ///< the material's name, or "room20"
  std::vector<std::pair<std::string, RealMaterial>> textured;
  bool room20 = false;
};

CaseSpec singleMaterial(const RealMaterial& m) {
  CaseSpec c;
  c.name = m.name;
  for (const std::string& part : kTexturedParts) c.textured.push_back({part, m});
  return c;
}

/// The timing case: 20 parts, each another material (in the order given).
CaseSpec room20Case(const std::vector<RealMaterial>& materials) {
  CaseSpec c;
  c.name = "room20";
  c.room20 = true;
  std::vector<std::string> parts = {"floor", "wall", "wall_left", "wall_right"};
  for (int k = 0; k < 8; ++k) {
    parts.push_back(fmt::format("top_{}", k));
    parts.push_back(fmt::format("side_{}", k));
  }
  for (size_t i = 0; i < parts.size() && !materials.empty(); ++i)
    c.textured.push_back({parts[i], materials[i % materials.size()]});
  return c;
}

struct Neutral {
  std::string part;
  Vec3d albedo;
  double roughness;
};
const std::vector<Neutral> kNeutral = {{"walls", {0.72, 0.70, 0.66}, 0.85},
                                       {"ceiling", {0.8, 0.8, 0.8}, 0.9},
                                       {"box_side", {0.35, 0.33, 0.31}, 0.6}};

// ---------------------------------------------------------------- generator

struct Options {
  fs::path data, work;
  std::string preset = "fast";
  int threads = 2, width = 320, height = 240, spp = 32, textureSize = 64;
  std::vector<std::string> lightings = {"warm", "window"};
  std::optional<SynthesisOptions> selection;  ///< the preset's when unset
  std::optional<bool> fitAllViews;            ///< PipelineOptions' default when unset
  std::optional<int> incidentSamples, incidentDirectSamples;  ///< the preset's when unset
  /// the method runs on scene_given.json: scene.json with each textured part's true category
  /// as `parts.<name>.category` (what the look reaches when the category is known)
  bool givenCategory = false;
};

/// Light through a window converges slower than a ceiling rectangle: twice the samples, so both
/// photos carry noise of a similar level.
int sppFor(const Options& o, const std::string& lighting) {
  return lighting == "window" ? 2 * o.spp : o.spp;
}

fs::path caseDir(const Options& o, const std::string& material, const std::string& lighting) {
  return o.work / "scenes" / material / lighting;
}

double percentileLuminance(const std::vector<cv::Mat>& images, double q) {
  std::vector<float> v;
  for (const cv::Mat& im : images)
    for (int y = 0; y < im.rows; ++y)
      for (int x = 0; x < im.cols; ++x) {
        const cv::Vec3f p = im.at<cv::Vec3f>(y, x);
        v.push_back(ps::luminance(p));
      }
  if (v.empty()) return 1;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return std::max(1e-6f, v[k]);
}

/// Writes one case folder (nothing when its scene.json exists already).
void generateCase(const Options& o, const CaseSpec& spec, const std::string& lighting) {
  const fs::path dir = caseDir(o, spec.name, lighting);
  if (fs::exists(dir / "scene.json")) return;
  const fs::path tmp = dir.string() + ".tmp";
  fs::remove_all(tmp);
  for (const char* sub : {"photos", "segments", "env", "gt/twin/materials", "gt/twin/textures"})
    fs::create_directories(tmp / sub);
  const bool window = lighting == "window";

  io::ObjMesh obj = roomMesh(window, spec.room20);
  const std::vector<Part> parts = tools::writeUvsIntoObj(obj);
  io::writeObj(tmp / "room.obj", obj);

  // true materials: the photographed maps on the textured parts, the neutral parts homogeneous
  struct Maps {
    fs::path normal;
    Vec3d albedoMean = Vec3d::Constant(0.5);
    double roughMean = 0.6;
  };
  std::map<std::string, Maps> mapsOf;
  for (const auto& [part, mat] : spec.textured) {
    if (mapsOf.count(mat.name)) continue;
    Maps& mp = mapsOf[mat.name];
    if (!mat.normal.empty()) {
      cv::Mat n = io::readDataImage(mat.normal);
      if (n.channels() == 1) cv::cvtColor(n, n, cv::COLOR_GRAY2RGB);
      if (mat.normalDirectX) {
        std::vector<cv::Mat> ch;
        cv::split(n, ch);
        ch[1] = 1.0 - ch[1];
        cv::merge(ch, n);
      }
      const std::string file = "normal_" + mat.name + ".png";
      io::WriteOptions lin;
      lin.encode = io::ColorSpace::Linear;
      lin.bits = 16;
      io::writeImage(tmp / "gt/twin/textures" / file, n, lin);
      mp.normal = fs::absolute(dir / "gt/twin/textures" / file);
    }
    const cv::Scalar a = cv::mean(io::readImage(mat.albedo));
    mp.albedoMean = Vec3d(a[0], a[1], a[2]);
    if (!mat.roughness.empty()) mp.roughMean = cv::mean(io::readDataImage(mat.roughness))[0];
  }
  Rng rng(fnv1a(spec.name) ^ (window ? 0x9e3779b97f4a7c15ull : 0));
  nlohmann::json truth = nlohmann::json::object();
  for (const auto& [part, mat] : spec.textured) {
    const Maps& mp = mapsOf.at(mat.name);
    io::MaterialFileDesc m;
    m.part = part;
    m.graph = "photo:" + mat.name;
    m.category = mat.category;
    m.uv.rotationDeg = 0;
    m.uv.scale = Vec2d::Constant(1.0 / periodFor(mat, part));
    m.uv.offset = Vec2d(rng.uniform(), rng.uniform());
    m.homogeneous.albedo = mp.albedoMean;
    m.homogeneous.roughness = mp.roughMean;
    m.maps["albedo"] = fs::absolute(mat.albedo);
    if (!mat.roughness.empty()) m.maps["roughness"] = fs::absolute(mat.roughness);
    if (!mp.normal.empty()) m.maps["normal"] = mp.normal;
    m.skipped = "ground truth (not fitted)";
    // written with paths relative to the final folder (the temporary one is renamed)
    io::writeMaterialJson(tmp / "gt/twin/materials" / (part + ".json"), m, dir / "gt/twin");
    truth[part] = {{"material", mat.name},
                   {"category", mat.category},
                   {"period_m", periodFor(mat, part)},
                   {"offset", {m.uv.offset.x(), m.uv.offset.y()}}};
  }
  nlohmann::json fixedParts = nlohmann::json::object();
  for (const Neutral& n : kNeutral) {
    if (std::find(obj.materialNames.begin(), obj.materialNames.end(), n.part) ==
        obj.materialNames.end())
      continue;
    io::MaterialFileDesc m;
    m.part = n.part;
    m.graph = m.category = "homogeneous";
    m.homogeneous.albedo = n.albedo;
    m.homogeneous.roughness = n.roughness;
    m.skipped = "ground truth (not fitted)";
    io::writeMaterialJson(tmp / "gt/twin/materials" / (n.part + ".json"), m, dir / "gt/twin");
    fixedParts[n.part] = {
        {"fixed",
         {{"albedo", {n.albedo.x(), n.albedo.y(), n.albedo.z()}}, {"roughness", n.roughness}}}};
  }

  // lights: the input leaves intensities to the fit; the truth's are exposed below
  nlohmann::json lights, gtLights;
  const Vec3d warm(1.0, 0.72, 0.45);
  if (window) {
    fs::copy_file(o.data / "examples/blender-room/env/forest.exr", tmp / "env/sky.exr");
    lights = {{"environment", {{"image", "env/sky.exr"}, {"window_parts", {"window"}}}}};
    gtLights = {
        {"environment",
         {{"image", "../../env/sky.exr"}, {"window_parts", {"window"}}, {"radiance", {1, 1, 1}}}}};
  } else {
    const nlohmann::json rect = {
        {"center", {-0.2, 2.59, -0.2}}, {"edge_u", {0.8, 0, 0}}, {"edge_v", {0, 0, 0.5}}};
    lights = {{"area", {rect}}};
    nlohmann::json r = rect;
    r["radiance"] = {warm.x(), warm.y(), warm.z()};
    gtLights = {{"area", {r}}};
  }
  const CaseGeometry geo = cameras(o.width, o.height);
  nlohmann::json views = nlohmann::json::array(), twinViews = nlohmann::json::array();
  for (int v = 0; v < 2; ++v) {
    const std::string photo = fmt::format("photos/view{}.png", v),
                      seg = fmt::format("segments/view{}.png", v);
    views.push_back({{"image", photo},
                     {"color_space", "srgb"},
                     {"camera", io::cameraToJson(geo.cams[v])},
                     {"segments", seg},
                     {"segment_parts", nlohmann::json::object()}});
    // placeholders of the right size let loadTwin validate before the renders exist
    io::writeImage(tmp / photo, cv::Mat(o.height, o.width, CV_32FC3, cv::Scalar(0, 0, 0)));
    io::writeRawImage(tmp / seg, cv::Mat(o.height, o.width, CV_16UC1, cv::Scalar(0)));
  }
  // the truth's scene.json in `caseFolder`: the views and gtLights as they stand
  auto writeTwinScene = [&](const fs::path& caseFolder) {
    for (int v = 0; v < 2; ++v) {
      twinViews[v] = views[v];
      twinViews[v]["image"] = "../../" + views[v]["image"].get<std::string>();
      twinViews[v]["segments"] = "../../" + views[v]["segments"].get<std::string>();
    }
    io::writeJsonFile(caseFolder / "gt/twin/scene.json", {{"version", 1},
                                                          {"geometry", "../../room.obj"},
                                                          {"up", {0, 1, 0}},
                                                          {"views", twinViews},
                                                          {"lights", gtLights}});
  };
  writeTwinScene(tmp);
  // scene.json places ceiling lights wherever it gives no area light; the truth of the window
  // lighting has none: its lights.json (which loadTwin prefers) holds the environment alone
  auto windowLights = [&](const fs::path& twinDir, double radiance) {
    io::writeJsonFile(twinDir / "lights.json", {{"emitters", nlohmann::json::array()},
                                                {"environment",
                                                 {{"image", "../../env/sky.exr"},
                                                  {"window_parts", {"window"}},
                                                  {"radiance", {radiance, radiance, radiance}}}},
                                                {"exposure", {1.0, 1.0}}});
  };
  if (window) windowLights(tmp / "gt/twin", 1.0);
  // loadTwin reads the maps through the final folder's relative paths: render in place
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  fs::rename(tmp, dir);
  try {
    Twin twin = loadTwin(dir / "gt/twin");
    RenderOptions ro;
    ro.spp = sppFor(o, lighting);
    std::vector<cv::Mat> imgs, offs;
    std::vector<GBuffer> gbs;
    {
      const PathTracer tracer(twin.scene, twin.materials);
      for (int v = 0; v < 2; ++v) {
        ro.seed = 1 + v;
        imgs.push_back(tracer.render(twin.scene.views[v].camera, ro));
        gbs.push_back(renderGBuffer(tracer, twin.scene.views[v].camera));
      }
    }
    // the true material, re-rendered with random UV offsets and another noise seed
    std::vector<PartMaterial> moved = twin.materials;
    for (PartMaterial& m : moved)
      if (std::any_of(spec.textured.begin(), spec.textured.end(),
                      [&](const auto& t) { return t.first == m.part; }))
        m.uv.offset += Vec2f(0.25f + 0.5f * rng.uniform(), 0.25f + 0.5f * rng.uniform());
    {
      const PathTracer tracer(twin.scene, moved);
      for (int v = 0; v < 2; ++v) {
        ro.seed = 101 + v;
        offs.push_back(tracer.render(twin.scene.views[v].camera, ro));
      }
    }
    const double exposure = 0.8 / percentileLuminance(imgs, 0.9);
    io::WriteOptions half;
    half.bits = 16;
    for (int v = 0; v < 2; ++v) {
      imgs[v] *= exposure;
      offs[v] *= exposure;
      io::writeImage(dir / fmt::format("gt/view{}.exr", v), imgs[v], half);
      io::writeImage(dir / fmt::format("gt/offset_view{}.exr", v), offs[v], half);
      io::writeImage(dir / fmt::format("photos/view{}.png", v), imgs[v]);
      cv::Mat labels(o.height, o.width, CV_16UC1, cv::Scalar(0));
      for (int y = 0; y < labels.rows; ++y)
        for (int x = 0; x < labels.cols; ++x) {
          const int p = gbs[v].partId.at<int>(y, x);
          if (p >= 0) labels.at<uint16_t>(y, x) = static_cast<uint16_t>(1000 + p);
        }
      io::writeRawImage(dir / fmt::format("segments/view{}.png", v), labels);
      for (const Part& p : parts)
        if (cv::countNonZero(labels == 1000 + p.id) > 0)
          views[v]["segment_parts"][std::to_string(1000 + p.id)] = p.name;
    }
    // the truth's lights as exposed
    if (window) {
      gtLights["environment"]["radiance"] = {exposure, exposure, exposure};
      windowLights(dir / "gt/twin", exposure);
    } else {
      gtLights["area"][0]["radiance"] = {exposure * warm.x(), exposure * warm.y(),
                                         exposure * warm.z()};
    }
    writeTwinScene(dir);
    io::writeJsonFile(dir / "gt/truth.json", {{"case", spec.name},
                                              {"lighting", lighting},
                                              {"spp", sppFor(o, lighting)},
                                              {"parts", truth}});
    // scene.json last: its presence marks the case as complete
    io::writeJsonFile(dir / "scene.json", {{"version", 1},
                                           {"geometry", "room.obj"},
                                           {"up", {0, 1, 0}},
                                           {"views", views},
                                           {"lights", lights},
                                           {"parts", fixedParts},
                                           {"options", {{"preset", o.preset}, {"seed", 0}}}});
  } catch (...) {
    fs::remove_all(dir);
    throw;
  }
}

// ---------------------------------------------------------------- runner and scoring

struct PartScore {
  std::string material, category, split, lighting, part;
  std::string graph, chosenCategory;
  nlohmann::json candidates = nlohmann::json::array();
  int fitPixels = 0;  ///< M_aln pixels in the fit view (materials file fit.pixels)
  int pixels = 0;     ///< scored pixels over both views
  double rmseMethod = NAN, rmseBaseline = NAN, rmseOffset = NAN;  ///< sRGB 0-255
  double distMethod = NAN, distBaseline = NAN, distOffset = NAN;  ///< texture distance to the photo
  double fitSeconds = 0;
  /// the part's mean roughness: fitted (materials/<part>.json homogeneous.roughness, the fit's held
  /// mean times the refine factor) and true (the mean of the material's roughness map, which
  /// tiles the part; 0.6 for a material without one)
  double roughnessFit = NAN, roughnessTrue = NAN;
};

/// Issue 17 item 5: fitted roughness within this of the truth.
constexpr double kRoughnessTolerance = 0.15;

struct CaseResult {
  std::vector<PartScore> parts;
  std::map<std::string, double> stageSeconds;  ///< method run
  double methodSeconds = 0, baselineSeconds = 0, generateSeconds = 0;
};

nlohmann::json toJson(const CaseResult& r) {
  nlohmann::json j;
  j["stages"] = r.stageSeconds;
  j["method_seconds"] = r.methodSeconds;
  j["baseline_seconds"] = r.baselineSeconds;
  j["generate_seconds"] = r.generateSeconds;
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  for (const PartScore& p : r.parts)
    j["parts"].push_back({{"material", p.material},
                          {"category", p.category},
                          {"split", p.split},
                          {"lighting", p.lighting},
                          {"part", p.part},
                          {"graph", p.graph},
                          {"chosen_category", p.chosenCategory},
                          {"candidates", p.candidates},
                          {"fit_pixels", p.fitPixels},
                          {"pixels", p.pixels},
                          {"rmse_method", num(p.rmseMethod)},
                          {"rmse_baseline", num(p.rmseBaseline)},
                          {"rmse_offset", num(p.rmseOffset)},
                          {"dist_method", num(p.distMethod)},
                          {"dist_baseline", num(p.distBaseline)},
                          {"dist_offset", num(p.distOffset)},
                          {"fit_seconds", p.fitSeconds},
                          {"roughness_fit", num(p.roughnessFit)},
                          {"roughness_true", num(p.roughnessTrue)}});
  return j;
}

CaseResult fromJson(const nlohmann::json& j) {
  CaseResult r;
  r.stageSeconds = j.at("stages").get<std::map<std::string, double>>();
  r.methodSeconds = j.at("method_seconds").get<double>();
  r.baselineSeconds = j.at("baseline_seconds").get<double>();
  r.generateSeconds = j.value("generate_seconds", 0.0);
  auto num = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
  for (const auto& p : j.at("parts")) {
    PartScore s;
    s.material = p.at("material");
    s.category = p.at("category");
    s.split = p.at("split");
    s.lighting = p.at("lighting");
    s.part = p.at("part");
    s.graph = p.at("graph");
    s.chosenCategory = p.at("chosen_category");
    s.candidates = p.at("candidates");
    s.fitPixels = p.at("fit_pixels");
    s.pixels = p.at("pixels");
    s.rmseMethod = num(p.at("rmse_method"));
    s.rmseBaseline = num(p.at("rmse_baseline"));
    s.rmseOffset = num(p.at("rmse_offset"));
    s.distMethod = num(p.at("dist_method"));
    s.distBaseline = num(p.at("dist_baseline"));
    s.distOffset = num(p.at("dist_offset"));
    s.fitSeconds = p.at("fit_seconds");
    if (p.contains("roughness_fit")) s.roughnessFit = num(p["roughness_fit"]);
    if (p.contains("roughness_true")) s.roughnessTrue = num(p["roughness_true"]);
    r.parts.push_back(s);
  }
  return r;
}

PipelineOptions pipelineOptions(const Options& o, const std::string& lighting,
                                const fs::path& scene, const fs::path& out, Baseline b) {
  PipelineOptions p;
  p.scene = scene;
  p.out = out;
  p.preset = o.preset;
  p.threads = o.threads;
  p.baseline = b;
  p.textureSize = o.textureSize;
  p.workWidth = o.width;
  p.renderSpp = sppFor(o, lighting);
  // the yardstick scores the fitted twin against a noisy photo at the photo's spp, raw as in
  // every earlier row of its tables (denoising would lower both the method's and the baseline's
  // RMSE by the render's noise and make old and new rows incomparable)
  p.denoise = false;
  p.writeReport = false;
  p.writeGltf = false;
  p.selection = o.selection;
  if (o.fitAllViews) p.fitAllViews = *o.fitAllViews;
  p.incidentSamples = o.incidentSamples;
  p.incidentDirectSamples = o.incidentDirectSamples;
  return p;
}

/// Fills the parts' fitted and true mean roughness from the case's materials files (results cached
/// before these columns existed get them from the run folders that are still there).
void readRoughness(const Options& o, const CaseSpec& spec, const std::string& lighting,
                   CaseResult& r) {
  const fs::path dir = caseDir(o, spec.name, lighting);
  const fs::path runs = o.work / "runs" / spec.name / lighting;
  auto roughnessIn = [](const fs::path& file) {
    if (!fs::exists(file)) return static_cast<double>(NAN);
    const nlohmann::json m = io::readJsonFile(file);
    if (!m.contains("homogeneous") || !m["homogeneous"].contains("roughness"))
      return static_cast<double>(NAN);
    return m["homogeneous"]["roughness"].get<double>();
  };
  for (PartScore& p : r.parts) {
    if (!std::isfinite(p.roughnessFit))
      p.roughnessFit = roughnessIn(runs / "method/materials" / (p.part + ".json"));
    if (!std::isfinite(p.roughnessTrue))
      p.roughnessTrue = roughnessIn(dir / "gt/twin/materials" / (p.part + ".json"));
  }
}

CaseResult runCase(const Options& o, const CaseSpec& spec, const std::string& lighting) {
  const fs::path dir = caseDir(o, spec.name, lighting);
  const fs::path runs = o.work / "runs" / spec.name / lighting;
  CaseResult r;
  fs::path methodScene = dir / "scene.json";
  if (o.givenCategory) {
    nlohmann::json given = io::readJsonFile(methodScene);
    for (const auto& [part, mat] : spec.textured) given["parts"][part]["category"] = mat.category;
    methodScene = dir / "scene_given.json";
    io::writeJsonFile(methodScene, given);
  }
  const PipelineResult method = runPipeline(
      pipelineOptions(o, lighting, methodScene, runs / "method", Baseline::None));
  for (const StageRecord& s : method.stages) r.stageSeconds[s.name] = s.seconds;
  r.methodSeconds = method.totalSeconds;
  // the baseline reads the same geometry, alignment and first lights: it starts from a copy of
  // the method's stage cache (keyed by their inputs), so only its own stages are computed
  if (!fs::exists(runs / "pixel-median/.cache") && fs::exists(runs / "method/.cache")) {
    fs::create_directories(runs / "pixel-median");
    fs::copy(runs / "method/.cache", runs / "pixel-median/.cache", fs::copy_options::recursive);
  }
  const PipelineResult base = runPipeline(pipelineOptions(
      o, lighting, dir / "scene.json", runs / "pixel-median", Baseline::PixelMedian));
  r.baselineSeconds = base.totalSeconds;

  const nlohmann::json sceneJson = io::readJsonFile(dir / "scene.json");
  std::map<std::string, int> labelOf;
  for (const auto& view : sceneJson.at("views"))
    for (const auto& [value, part] : view.at("segment_parts").items())
      labelOf[part.get<std::string>()] = std::stoi(value);
  for (const auto& [part, mat] : spec.textured) {
    PartScore s;
    s.material = mat.name;
    s.category = mat.category;
    s.split = splitOf(mat.name);
    s.lighting = lighting;
    s.part = part;
    const nlohmann::json m = io::readJsonFile(runs / "method/materials" / (part + ".json"));
    s.graph = m.value("graph", "");
    s.chosenCategory = m.value("category", "");
    if (m.contains("fit")) {
      const nlohmann::json& f = m["fit"];
      if (f.contains("candidates")) s.candidates = f["candidates"];
      s.fitPixels = f.value("pixels", 0);
      if (f.contains("seconds") && f["seconds"].is_number())
        s.fitSeconds = f["seconds"].get<double>();
    }
    double seM = 0, seB = 0, seO = 0, wD = 0, dM = 0, dB = 0, dO = 0;
    int n = 0;
    for (int v = 0; v < 2; ++v) {
      if (!labelOf.count(part)) continue;
      const cv::Mat labels = io::readLabelImage(dir / fmt::format("segments/view{}.png", v));
      cv::Mat mask = labels == labelOf[part];
      cv::erode(mask, mask, cv::Mat());
      const int px = cv::countNonZero(mask);
      if (px == 0) continue;
      const cv::Mat photo = io::readImage(dir / fmt::format("photos/view{}.png", v));
      const cv::Mat fitted = io::readImage(runs / fmt::format("method/renders/view{}.exr", v));
      const cv::Mat baseline =
          io::readImage(runs / fmt::format("pixel-median/renders/view{}.exr", v));
      const cv::Mat offset = io::readImage(dir / fmt::format("gt/offset_view{}.exr", v));
      auto se = [&](const cv::Mat& img) {
        const double e = eval::rmse(img, photo, eval::ColorSpace::Srgb255, mask);
        return e * e * px;
      };
      seM += se(fitted);
      seB += se(baseline);
      seO += se(offset);
      n += px;
      // the distance needs a region with texture to describe: views where the part is tiny are
      // left out of it (not of the RMSE)
      if (px >= 64) {
        const eval::TextureHistograms hp = eval::textureHistograms(photo, mask);
        dM += px * eval::textureDistance(hp, eval::textureHistograms(fitted, mask)).total;
        dB += px * eval::textureDistance(hp, eval::textureHistograms(baseline, mask)).total;
        dO += px * eval::textureDistance(hp, eval::textureHistograms(offset, mask)).total;
        wD += px;
      }
    }
    s.pixels = n;
    if (n > 0) {
      s.rmseMethod = std::sqrt(seM / n);
      s.rmseBaseline = std::sqrt(seB / n);
      s.rmseOffset = std::sqrt(seO / n);
    }
    if (wD > 0) {
      s.distMethod = dM / wD;
      s.distBaseline = dB / wD;
      s.distOffset = dO / wD;
    }
    r.parts.push_back(s);
  }
  readRoughness(o, spec, lighting, r);
  return r;
}

// ---------------------------------------------------------------- reports

std::string candidatesText(const nlohmann::json& c) {
  std::string s;
  for (const auto& x : c) {
    if (!s.empty()) s += " ";
    s += fmt::format("{}:{:.2f}", x.value("graph", "?"), x.value("score", 0.0));
  }
  return s.empty() ? "-" : s;
}

struct Summary {
  int parts = 0, catParts = 0, catRight = 0, distParts = 0, rmseParts = 0, rmseWins = 0;
  int roughParts = 0, roughWithin = 0;
  double roughAbsErr = 0;
  double distMethod = 0, distOffset = 0, distBaseline = 0, rmseMethod = 0, rmseBaseline = 0;
};

Summary summarise(const std::vector<PartScore>& rows, const std::string& split) {
  Summary s;
  for (const PartScore& p : rows) {
    if (split != "all" && p.split != split) continue;
    ++s.parts;
    if (p.fitPixels >= kCategoryMinPixels) {
      ++s.catParts;
      s.catRight += p.chosenCategory == p.category;
    }
    if (std::isfinite(p.distMethod) && std::isfinite(p.distOffset)) {
      ++s.distParts;
      s.distMethod += p.distMethod;
      s.distOffset += p.distOffset;
      s.distBaseline += p.distBaseline;
    }
    if (std::isfinite(p.roughnessFit) && std::isfinite(p.roughnessTrue)) {
      ++s.roughParts;
      const double e = std::abs(p.roughnessFit - p.roughnessTrue);
      s.roughWithin += e <= kRoughnessTolerance;
      s.roughAbsErr += e;
    }
    if (std::isfinite(p.rmseMethod) && std::isfinite(p.rmseBaseline)) {
      ++s.rmseParts;
      s.rmseMethod += p.rmseMethod;
      s.rmseBaseline += p.rmseBaseline;
      s.rmseWins += p.rmseMethod <= p.rmseBaseline;
    }
  }
  if (s.distParts) {
    s.distMethod /= s.distParts;
    s.distOffset /= s.distParts;
    s.distBaseline /= s.distParts;
  }
  if (s.roughParts) s.roughAbsErr /= s.roughParts;
  if (s.rmseParts) {
    s.rmseMethod /= s.rmseParts;
    s.rmseBaseline /= s.rmseParts;
  }
  return s;
}

void printSummary(const std::vector<PartScore>& rows, const std::string& split) {
  const Summary s = summarise(rows, split);
  const double ratio = s.distOffset > 0 ? s.distMethod / s.distOffset : NAN;
  std::printf(
      "%-5s  parts %3d | category right %3d/%3d = %5.1f %% (parts >= %d px; bar 80 %%) | texture "
      "distance "
      "fit %.3f, true+offset %.3f, ratio %.2f (bar 1.50), pixel-median %.3f | masked RMSE (sRGB "
      "0-255) fit "
      "%.2f vs pixel-median %.2f, fit <= baseline on %d/%d parts\n",
      split.c_str(), s.parts, s.catRight, s.catParts,
      s.catParts ? 100.0 * s.catRight / s.catParts : NAN, kCategoryMinPixels, s.distMethod,
      s.distOffset, ratio, s.distBaseline, s.rmseMethod, s.rmseBaseline, s.rmseWins, s.rmseParts);
  std::printf(
      "%-5s  roughness: fitted within %.2f of the truth on %d/%d parts = %5.1f %% (bar 80 %%), "
      "mean "
      "|error| %.3f\n",
      split.c_str(), kRoughnessTolerance, s.roughWithin, s.roughParts,
      s.roughParts ? 100.0 * s.roughWithin / s.roughParts : NAN, s.roughAbsErr);
}

void printConfusion(const std::vector<PartScore>& rows, const std::string& split) {
  std::map<std::string, std::map<std::string, int>> table;
  std::set<std::string> cols;
  for (const PartScore& p : rows) {
    if ((split != "all" && p.split != split) || p.fitPixels < kCategoryMinPixels) continue;
    table[p.category][p.chosenCategory]++;
    cols.insert(p.chosenCategory);
  }
  std::printf("\ncategory confusion (%s; parts >= %d px; rows: true, columns: chosen)\n%-10s",
              split.c_str(), kCategoryMinPixels, "");
  for (const std::string& c : cols) std::printf(" %8.8s", c.c_str());
  std::printf("   right\n");
  for (const auto& [truth, row] : table) {
    std::printf("%-10s", truth.c_str());
    int total = 0, right = 0;
    for (const std::string& c : cols) {
      const int n = row.count(c) ? row.at(c) : 0;
      total += n;
      if (c == truth) right = n;
      if (n)
        std::printf(" %8d", n);
      else
        std::printf(" %8s", ".");
    }
    std::printf("   %d/%d\n", right, total);
  }
}

// ---------------------------------------------------------------- recognition ceiling

/// A material's maps at `size` texels: linear albedo and unit OpenGL normals (flat without a
/// normal map), for the canonical patch.
MaterialMaps loadMaps(const RealMaterial& m, int size) {
  MaterialMaps maps;
  cv::resize(io::readImage(m.albedo), maps.albedo, {size, size}, 0, 0, cv::INTER_AREA);
  if (m.normal.empty()) {
    maps.normal = cv::Mat(size, size, CV_32FC3, cv::Scalar(0, 0, 1));
    return maps;
  }
  maps.normal = bench::loadNormalMap(m.normal, m.normalDirectX, size);
  return maps;
}

/// How far the texture key can tell a photographed material's category when nothing stands in
/// the way: each material drawn flat, frontal, evenly lit and noise-free (the bank's canonical
/// patch, 3 UV scales x 2 rotations), named (a) by the bank's category vote, summed over its
/// renders, and (b) by the category of the nearest render of another `tune` material in the
/// bank's indexed key space (real exemplars in place of the graphs' draws; leave-one-out on
/// `tune`). The pipeline's category accuracy on parts in a room sits below (a), and (b) says
/// whether real exemplars would do better. Prints a row per material and each half's accuracy,
/// with the share of the `tune` half's most common category for chance.
void recognitionCeiling(const std::vector<RealMaterial>& materials, const fs::path& bankCache) {
  const GraphLibrary library = GraphLibrary::load();
  const ExemplarBank bank = ExemplarBank::loadOrBuild(library, {}, bankCache);
  const ExemplarBankOptions& bo = bank.options();
  const std::vector<float> scales = {1.61f, 2.84f, 5.0f}, rotations = {0.f, 30.f};
  struct Render {
    size_t material;
    std::vector<float> key;              ///< indexed (projected) key
    eval::TextureHistograms histograms;  ///< the evaluation's texture statistics
  };
  std::vector<Render> renders;
  std::vector<std::map<std::string, double>> votes(materials.size());
  const cv::Mat mask(bo.renderSize, bo.renderSize, CV_8UC1, cv::Scalar(255));
  for (size_t i = 0; i < materials.size(); ++i) {
    const MaterialMaps maps = loadMaps(materials[i], bo.mapSize);
    for (float s : scales)
      for (float r : rotations) {
        const cv::Mat patch = renderCanonicalPatch(maps, bo.renderSize, s, r);
        const std::vector<float> raw = describeTexture(patch, mask, bo);
        const GraphChoice c = bank.select(raw);
        double total = 0;
        for (const GraphVote& v : c.categoryVotes) total += v.weight;
        for (const GraphVote& v : c.categoryVotes) votes[i][v.category] += v.weight / total;
        renders.push_back({i, bank.project(raw), eval::textureHistograms(patch, mask)});
      }
  }
  auto argmax = [](const std::map<std::string, double>& m) {
    std::string best;
    double w = -1;
    for (const auto& [k, v] : m)
      if (v > w) std::tie(best, w) = std::tie(k, v);
    return best;
  };
  std::map<std::string, double> tuneCategories;
  for (const RealMaterial& m : materials)
    if (splitOf(m.name) == "tune") tuneCategories[m.category] += 1;
  const std::string common = argmax(tuneCategories);
  // the category of the nearest render of another tune material, by a distance between renders
  auto nearestTune = [&](size_t i, auto distance) {
    std::map<std::string, double> count;
    for (const Render& q : renders) {
      if (q.material != i) continue;
      double best = 1e300;
      std::string category;
      for (const Render& e : renders) {
        if (e.material == i || splitOf(materials[e.material].name) != "tune") continue;
        const double d = distance(q, e);
        if (d < best) std::tie(best, category) = std::tie(d, materials[e.material].category);
      }
      count[category] += 1;
    }
    return argmax(count);
  };
  auto keyDistance = [](const Render& a, const Render& b) {
    double d = 0;
    for (size_t k = 0; k < a.key.size(); ++k) d += (a.key[k] - b.key[k]) * (a.key[k] - b.key[k]);
    return d;
  };
  auto histogramDistance = [](const Render& a, const Render& b) {
    return eval::textureDistance(a.histograms, b.histograms).total;
  };
  // split -> materials, right by the vote, by the nearest key, by the nearest histograms, chance
  std::map<std::string, std::array<int, 5>> tally;
  std::printf("%-40s %-9s %-6s %-10s %-10s %-10s\n", "material", "category", "split", "bank vote",
              "near key", "near hist");
  for (size_t i = 0; i < materials.size(); ++i) {
    const RealMaterial& m = materials[i];
    const std::string vote = argmax(votes[i]), byKey = nearestTune(i, keyDistance),
                      byHist = nearestTune(i, histogramDistance);
    std::array<int, 5>& t = tally[splitOf(m.name)];
    t[0]++;
    t[1] += vote == m.category;
    t[2] += byKey == m.category;
    t[3] += byHist == m.category;
    t[4] += common == m.category;
    std::printf("%-40s %-9s %-6s %-10s %-10s %-10s\n", m.name.c_str(), m.category.c_str(),
                splitOf(m.name).c_str(), vote.c_str(), byKey.c_str(), byHist.c_str());
  }
  for (const auto& [split, t] : tally)
    std::printf(
        "%-5s: %2d materials; category right by the bank's vote %2d (%.0f %%), by the "
        "nearest tune material's key %2d (%.0f %%), by its texture histograms %2d (%.0f %%); "
        "always '%s' %2d (%.0f %%)\n",
        split.c_str(), t[0], t[1], 100.0 * t[1] / t[0], t[2], 100.0 * t[2] / t[0], t[3],
        100.0 * t[3] / t[0], common.c_str(), t[4], 100.0 * t[4] / t[0]);
}

/// Photo crop | twin crop per part (view 0 of the warm lighting), one row per material.
void contactSheet(const Options& o, const std::vector<std::string>& materials,
                  const std::vector<PartScore>& rows, const fs::path& file) {
  const int tile = 84, label = 150, caption = 14;
  const std::string lighting = o.lightings.front();
  std::vector<std::string> mats;
  for (const std::string& m : materials)
    if (fs::exists(o.work / "runs" / m / lighting / "method/renders/view0.exr")) mats.push_back(m);
  if (mats.empty()) return;
  const int W = label + static_cast<int>(kTexturedParts.size()) * (2 * tile + 6);
  const int H = 20 + static_cast<int>(mats.size()) * (tile + caption + 4);
  cv::Mat sheet(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  int x0 = label;
  for (const std::string& part : kTexturedParts) {
    cv::putText(sheet, part + ": photo | twin", {x0, 14}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0},
                1, cv::LINE_AA);
    x0 += 2 * tile + 6;
  }
  int y0 = 20;
  for (const std::string& m : mats) {
    const fs::path dir = caseDir(o, m, lighting), run = o.work / "runs" / m / lighting / "method";
    const nlohmann::json sceneJson = io::readJsonFile(dir / "scene.json");
    std::map<std::string, int> labelOf;
    for (const auto& [value, part] : sceneJson["views"][0].at("segment_parts").items())
      labelOf[part.get<std::string>()] = std::stoi(value);
    const cv::Mat labels = io::readLabelImage(dir / "segments/view0.png");
    cv::Mat photo8, twin8;
    auto to8 = [](const cv::Mat& lin) {
      cv::Mat s = eval::toMetricSpace(lin, eval::ColorSpace::Srgb255), out;
      s.convertTo(out, CV_8UC3);
      return out;
    };
    photo8 = to8(io::readImage(dir / "photos/view0.png"));
    twin8 = to8(io::readImage(run / "renders/view0.exr"));
    std::string cat;
    for (const PartScore& p : rows)
      if (p.material == m) cat = p.category;
    cv::putText(sheet, m.substr(0, 24), {4, y0 + caption + tile / 2}, cv::FONT_HERSHEY_SIMPLEX,
                0.33, {0, 0, 0}, 1, cv::LINE_AA);
    cv::putText(sheet, "(" + cat + ", " + splitOf(m) + ")", {4, y0 + caption + tile / 2 + 14},
                cv::FONT_HERSHEY_SIMPLEX, 0.33, {0, 0, 0}, 1, cv::LINE_AA);
    x0 = label;
    for (const std::string& part : kTexturedParts) {
      if (labelOf.count(part)) {
        const cv::Mat mask = labels == labelOf[part];
        const cv::Rect box = cv::boundingRect(mask);
        if (box.area() > 0) {
          for (int k = 0; k < 2; ++k) {
            cv::Mat crop = (k == 0 ? photo8 : twin8)(box).clone();
            crop.setTo(cv::Scalar(255, 255, 255), ~mask(box));
            const double s = std::min(static_cast<double>(tile) / box.width,
                                      static_cast<double>(tile) / box.height);
            cv::Mat r;
            cv::resize(crop, r,
                       cv::Size(std::max(1, static_cast<int>(box.width * s)),
                                std::max(1, static_cast<int>(box.height * s))),
                       0, 0, cv::INTER_AREA);
            r.copyTo(sheet(cv::Rect(x0 + k * tile, y0 + caption, r.cols, r.rows)));
          }
        }
      }
      for (const PartScore& p : rows)
        if (p.material == m && p.lighting == lighting && p.part == part) {
          const cv::Scalar color =
              p.chosenCategory == p.category ? cv::Scalar(0, 120, 0) : cv::Scalar(200, 0, 0);
          // the chosen graph above its crops (below them it read as the next row's)
          cv::putText(sheet, p.graph.substr(0, 26), {x0 + tile / 2, y0 + caption - 4},
                      cv::FONT_HERSHEY_SIMPLEX, 0.32, color, 1, cv::LINE_AA);
        }
      x0 += 2 * tile + 6;
    }
    y0 += tile + caption + 4;
  }
  fs::create_directories(file.parent_path().empty() ? fs::path(".") : file.parent_path());
  io::writeRawImage(file, sheet);  // 8-bit RGB as it is
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  initLogging(LogLevel::Warn);
  CLI::App app{
      "real-texture yardstick: photographed materials in a path-traced room, through the pipeline"};
  Options o;
  o.data = PS_SHARED_DATA;
  o.work = "real-textures";
  std::string materialsArg, lightingsArg = "warm,window", splitArg = "all", csvArg, sheetArg;
  int limit = 0, sheetRows = 12;
  bool check = false, force = false, cachedOnly = false, room20 = false, recognise = false;
  app.add_option("--data", o.data, "shared data folder");
  app.add_option("--work", o.work, "work folder (cases, runs, per-case results; reused)");
  app.add_option("--materials", materialsArg, "comma list of material names (default: all)");
  app.add_option("--limit", limit, "at most N materials (after the filters)");
  app.add_option("--split", splitArg, "all | tune | check");
  app.add_option("--lightings", lightingsArg, "comma list of warm, window");
  app.add_option("--preset", o.preset, "pipeline preset of the method");
  app.add_option("--threads", o.threads, "threads (0 = all cores)");
  // selection by synthesis (select/synthesis.hpp), for the accuracy-against-time sweep: any of
  // these replaces the preset's settings by the preset's own (synthesisPreset) plus the ones given
  SynthesisOptions synthesis;
  int startDraw = SynthesisOptions{}.startFromNearestDraw,
      warmFit = SynthesisOptions{}.warmStartFit, heldOut = SynthesisOptions{}.heldOut,
      textureRequired = SynthesisOptions{}.textureRequired;
  app.add_option("--select-shortlist", synthesis.shortlist, "graphs of the vote fitted on the part");
  app.add_option("--select-categories", synthesis.categories, "categories among the finalists");
  app.add_option("--select-steps", synthesis.steps, "Adam steps of each finalist");
  app.add_option("--select-vote-k", synthesis.voteK, "neighbours of the vote listing finalists");
  app.add_option("--select-margin", synthesis.textureMargin, "a graph beats homogeneous by this");
  app.add_option("--select-pixel-ratio", synthesis.maxPixelErrorRatio,
                 "a graph's pixel RMSE at most this x homogeneous's (0: no test)");
  app.add_option("--select-contrast-ratio", synthesis.maxContrastRatio,
                 "a graph's typical local contrast at most this x the photo's (0: no test)");
  app.add_option("--select-chroma-ratio", synthesis.maxChromaRatio,
                 "a graph's chromaticity spread at most this x the photo's (0: no test)");
  app.add_option("--select-chroma-outside", synthesis.maxChromaOutside,
                 "at most this share of a graph's render in colours the photo lacks (0: no test)");
  float selectShape = 0.0f;
  app.add_option("--select-shape", selectShape,
                 "the spectral shape's weight in the finalists' short fits (bandShape)");
  app.add_option("--select-coarse-scale", synthesis.coarseContrastScale,
                 "the contrast test again at this many pixels per cell (0 or 1: no such test)");
  app.add_option("--select-start-draw", startDraw,
                 "1: finalists start from their nearest draw, 0: from their defaults");
  app.add_option("--select-warm-fit", warmFit,
                 "1: the fit goes on from the synthesis winner, 0: starts from the defaults");
  app.add_option("--select-held-out", heldOut,
                 "1: finalists fitted on one half of a part, scored on the other; 0: on the whole");
  app.add_option("--select-texture-required", textureRequired,
                 "1: a part whose category is given gets one of its graphs whatever the "
                 "homogeneous loss (with --given-category); 0: weighed against it");
  std::string fitViews;
  app.add_option("--fit-views", fitViews,
                 "best: each part fitted in the view that sees it best; all: a homogeneous part over "
                 "every view that sees it well (default: the pipeline's)")
      ->check(CLI::IsMember({"best", "all"}));
  int incidentSamples = 0, incidentDirect = -1;
  app.add_option("--incident-samples", incidentSamples,
                 "incident-light grids: path samples per bin (0: the preset's)");
  app.add_option("--incident-direct", incidentDirect,
                 "incident-light grids: light samples per lamp at each point (-1: the preset's)");
  app.add_option("--width", o.width);
  app.add_option("--height", o.height);
  app.add_option("--spp", o.spp,
                 "samples per pixel of the photos, the offset truth and the pipeline's renders");
  app.add_option("--texture-size", o.textureSize, "exported maps (the renders read them)");
  app.add_option("--csv", csvArg, "per-part CSV");
  app.add_option("--sheet", sheetArg, "contact sheet PNG (photo | twin crop per part)");
  app.add_option("--sheet-rows", sheetRows, "materials on the contact sheet (check half first)");
  app.add_flag("--check", check,
               "ctest mode: exit 1 unless every number is finite and every part reported");
  app.add_flag("--force", force, "rerun the cases whose results are cached");
  app.add_flag("--given-category", o.givenCategory,
               "the method is told each textured part's true category (parts.<name>.category): "
               "the look reached when recognition is right (use its own --work)");
  app.add_flag(
      "--room20", room20,
      "the timing case instead: one room whose 20 parts wear 20 materials (the first 20 chosen), "
      "the first lighting only");
  app.add_flag("--recognise", recognise,
               "the recognition ceiling instead: each material flat and frontal, its category by "
               "the bank's vote and by the nearest tune material (no room, no pipeline)");
  app.add_flag("--cached-only", cachedOnly,
               "report only the cases whose results are cached (run nothing)");
  CLI11_PARSE(app, argc, argv);
  o.lightings = splitList(lightingsArg);
  if (!fitViews.empty()) o.fitAllViews = fitViews == "all";
  if (incidentSamples > 0) o.incidentSamples = incidentSamples;
  if (incidentDirect >= 0) o.incidentDirectSamples = incidentDirect;
  for (const char* flag : {"--select-shortlist", "--select-categories", "--select-steps",
                           "--select-vote-k", "--select-margin", "--select-pixel-ratio",
                           "--select-contrast-ratio", "--select-chroma-ratio",
                           "--select-chroma-outside", "--select-coarse-scale",
                           "--select-start-draw", "--select-warm-fit", "--select-held-out",
                           "--select-shape", "--select-texture-required"})
    if (app.count(flag) > 0) {
      SynthesisOptions s = synthesisPreset(o.preset);
      if (app.count("--select-shortlist")) s.shortlist = synthesis.shortlist;
      if (app.count("--select-categories")) s.categories = synthesis.categories;
      if (app.count("--select-steps")) s.steps = synthesis.steps;
      if (app.count("--select-vote-k")) s.voteK = synthesis.voteK;
      if (app.count("--select-margin")) s.textureMargin = synthesis.textureMargin;
      if (app.count("--select-pixel-ratio")) s.maxPixelErrorRatio = synthesis.maxPixelErrorRatio;
      if (app.count("--select-contrast-ratio")) s.maxContrastRatio = synthesis.maxContrastRatio;
      if (app.count("--select-coarse-scale")) s.coarseContrastScale = synthesis.coarseContrastScale;
      if (app.count("--select-chroma-ratio")) s.maxChromaRatio = synthesis.maxChromaRatio;
      if (app.count("--select-chroma-outside")) s.maxChromaOutside = synthesis.maxChromaOutside;
      if (app.count("--select-shape")) s.bandShape = selectShape;
      s.startFromNearestDraw = startDraw != 0;
      s.warmStartFit = warmFit != 0;
      s.heldOut = heldOut != 0;
      s.textureRequired = textureRequired != 0;
      o.selection = s;
    }

  if (!fs::exists(o.data / "textures/cc0/manifest.json")) {
    std::printf("SKIP: no %s\n", (o.data / "textures/cc0/manifest.json").string().c_str());
    return kSkipCode;
  }
  try {
    ThreadLimit threads(o.threads > 0 ? o.threads : 0);
    std::vector<RealMaterial> all = bench::listRealMaterials(o.data), chosen;
    const std::vector<std::string> wanted = splitList(materialsArg);
    for (const RealMaterial& m : all) {
      if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), m.name) == wanted.end())
        continue;
      if (splitArg != "all" && splitOf(m.name) != splitArg) continue;
      chosen.push_back(m);
    }
    // check half first, so a partial run has the numbers that count; within a half, one material
    // of each category in turn, so a partial run covers the categories
    {
      std::map<std::string, int> rank;
      std::vector<std::pair<std::tuple<int, int, size_t>, RealMaterial>> keyed;
      for (size_t i = 0; i < chosen.size(); ++i) {
        const RealMaterial& m = chosen[i];
        const int r = rank[splitOf(m.name) + "/" + m.category]++;
        keyed.push_back({{splitOf(m.name) == "check" ? 0 : 1, r, i}, m});
      }
      std::sort(keyed.begin(), keyed.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      chosen.clear();
      for (auto& k : keyed) chosen.push_back(k.second);
    }
    if (limit > 0 && static_cast<int>(chosen.size()) > limit) chosen.resize(limit);
    if (recognise) {
      // every material of the manifest (tune is the reference), whatever the filters chose
      recognitionCeiling(all, defaultBankCache());
      return 0;
    }
    for (const std::string& w : wanted)
      if (std::none_of(all.begin(), all.end(), [&](const RealMaterial& m) { return m.name == w; }))
        throw InputError("--materials", w, "a material name of the manifest");

    std::vector<PartScore> rows;
    std::map<std::string, double> stageSum;
    double methodSum = 0, baselineSum = 0;
    int cases = 0, failed = 0;
    bool ok = true;
    std::printf("%-36s %-9s %-6s %-11s %-24s %-10s %6s %7s %7s %6s %6s %6s %5s %5s  %s\n",
                "material", "category", "split", "part", "graph (lighting)", "chosen cat", "px",
                "RMSE", "median", "dist", "offset", "fit s", "r fit", "r tru",
                "top-5 (vote share)");
    std::vector<CaseSpec> specs;
    if (room20) {
      specs.push_back(room20Case(chosen));
      o.lightings = {o.lightings.front()};
    } else {
      for (const RealMaterial& m : chosen) specs.push_back(singleMaterial(m));
    }
    for (const CaseSpec& spec : specs)
      for (const std::string& lighting : o.lightings) {
        const fs::path result = o.work / "results" / (spec.name + "_" + lighting + ".json");
        CaseResult r;
        if (fs::exists(result) && !force) {
          r = fromJson(io::readJsonFile(result));
          readRoughness(o, spec, lighting, r);
        } else if (cachedOnly) {
          continue;
        } else {
          // a case that fails is reported and left out; the others go on
          try {
            Timer t;
            generateCase(o, spec, lighting);
            const double gen = t.seconds();
            r = runCase(o, spec, lighting);
            r.generateSeconds = gen;
            fs::create_directories(result.parent_path());
            io::writeJsonFile(result, toJson(r));
          } catch (const Interrupted&) {
            throw;
          } catch (const std::exception& e) {
            std::printf("FAILED %s (%s): %s\n", spec.name.c_str(), lighting.c_str(), e.what());
            ++failed;
            ok = false;
            continue;
          }
        }
        ++cases;
        for (const auto& [k, v] : r.stageSeconds) stageSum[k] += v;
        methodSum += r.methodSeconds;
        baselineSum += r.baselineSeconds;
        for (const PartScore& p : r.parts) {
          std::printf(
              "%-36s %-9s %-6s %-11s %-24s %-10s %6d %7.2f %7.2f %6.3f %6.3f %6.1f %5.2f %5.2f  "
              "%s\n",
              p.material.c_str(), p.category.c_str(), p.split.c_str(), p.part.c_str(),
              (p.graph + " (" + p.lighting + ")").substr(0, 24).c_str(), p.chosenCategory.c_str(),
              p.fitPixels, p.rmseMethod, p.rmseBaseline, p.distMethod, p.distOffset, p.fitSeconds,
              p.roughnessFit, p.roughnessTrue, candidatesText(p.candidates).c_str());
          std::fflush(stdout);
          rows.push_back(p);
          for (double v : {p.rmseMethod, p.rmseBaseline, p.rmseOffset, p.distMethod, p.distOffset,
                           p.fitSeconds})
            if (!std::isfinite(v)) ok = false;
        }
        if (r.parts.size() != spec.textured.size() || !std::isfinite(r.methodSeconds)) ok = false;
      }

    if (failed) std::printf("\n%d cases FAILED (above)\n", failed);
    std::printf(
        "\nsummary (%d cases = materials x lightings, %d parts; category on the parts the fit view "
        "sees with >= %d px)\n",
        cases, static_cast<int>(rows.size()), kCategoryMinPixels);
    for (const char* split : {"tune", "check", "all"}) printSummary(rows, split);
    if (cases > 0) {
      std::printf("\nseconds per case (mean): method %.1f (", methodSum / cases);
      bool first = true;
      for (const auto& [k, v] : stageSum) {
        std::printf("%s%s %.1f", first ? "" : ", ", k.c_str(), v / cases);
        first = false;
      }
      std::printf("), pixel-median baseline %.1f; %s preset, %d threads, %dx%d, %d spp\n",
                  baselineSum / cases, o.preset.c_str(), o.threads, o.width, o.height, o.spp);
    }
    for (const char* split : {"tune", "check"}) printConfusion(rows, split);

    if (!csvArg.empty()) {
      std::ofstream csv(csvArg);
      csv << "material,category,split,lighting,part,graph,chosen_category,category_right,fit_"
             "pixels,scored_pixels,"
             "rmse_fit_srgb255,rmse_pixel_median_srgb255,rmse_true_offset_srgb255,dist_fit,dist_"
             "pixel_median,"
             "dist_true_offset,fit_seconds,roughness_fit,roughness_true,top5\n";
      for (const PartScore& p : rows)
        csv << p.material << ',' << p.category << ',' << p.split << ',' << p.lighting << ','
            << p.part << ',' << p.graph << ',' << p.chosenCategory << ','
            << (p.chosenCategory == p.category) << ',' << p.fitPixels << ',' << p.pixels << ','
            << p.rmseMethod << ',' << p.rmseBaseline << ',' << p.rmseOffset << ',' << p.distMethod
            << ',' << p.distBaseline << ',' << p.distOffset << ',' << p.fitSeconds << ','
            << p.roughnessFit << ',' << p.roughnessTrue << ",\"" << candidatesText(p.candidates)
            << "\"\n";
    }
    if (!sheetArg.empty()) {
      std::vector<std::string> names;
      for (const RealMaterial& m : chosen) names.push_back(m.name);
      // one material per category first (check half first), then the rest, up to sheetRows
      std::vector<std::string> pick;
      std::set<std::string> seen;
      for (const RealMaterial& m : chosen)
        if (seen.insert(m.category).second) pick.push_back(m.name);
      for (const std::string& n : names)
        if (std::find(pick.begin(), pick.end(), n) == pick.end()) pick.push_back(n);
      if (static_cast<int>(pick.size()) > sheetRows) pick.resize(sheetRows);
      contactSheet(o, pick, rows, sheetArg);
    }
    if (check && (!ok || cases != static_cast<int>(specs.size() * o.lightings.size()))) {
      std::printf("CHECK FAILED: a number is not finite or a part is missing\n");
      return 1;
    }
  } catch (const Interrupted& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 130;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
