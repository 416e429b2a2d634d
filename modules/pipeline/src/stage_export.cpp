// Stage `export`: the output folder of ../shared/spec/scene-format.md section 3 (textures at
// --texture-size with the graphs evaluated there, materials/*.json, lights.json, scene.json,
// renders, twin.gltf), every file written whole (temporary name + rename). It reads the whole
// scene.json: the twin's scene.json is the input's, extended.
#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/report.hpp"
#include "stages.hpp"

namespace ps::pipeline {

namespace {

void copyFile(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  io::writeAtomically(to, [&](const fs::path& tmp) {
    fs::copy_file(from, tmp, fs::copy_options::overwrite_existing);
  });
}

int nextPowerOfTwo(int n) {
  int p = 4;
  while (p < n) p *= 2;
  return p;
}

cv::Mat atSize(const cv::Mat& m, int size) {
  if (m.empty() || m.cols == size) return m;
  cv::Mat out;
  cv::resize(m, out, cv::Size(size, size), 0, 0, cv::INTER_AREA);
  return out;
}

// The maps of a fitted part at the texture size: the graph re-evaluated at the next power of two,
// and at least at the fit's map size, then area-downsampled to the size. Below the fit's size a
// graph drawn directly is not the fitted map made smaller: a pattern finer than a texel aliases
// (fabric_windowpane's grid drawn at 64 texels kept its vertical lines only, each a texel wide,
// and the twin rendered dark stripes that the fit, at 128, never saw).
void writeTextures(const Reads& in, const PartWork& p, io::MaterialFileDesc& m,
                   const fs::path& out) {
  const int size = in.textureSize();
  MaterialGraph g = in.library().create(p.graph);
  g.setValues(p.values);
  const MaterialMaps maps =
      g.evaluate(std::max(nextPowerOfTwo(size), nextPowerOfTwo(in.fitOptions().mapSize)),
                 MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
  const fs::path tex = out / "textures";
  fs::create_directories(tex);
  const cv::Mat albedo = atSize(maps.albedo, size);
  io::writeImage(tex / (p.name + "_albedo.png"), albedo);
  cv::Mat n = atSize(maps.normal, size);
  // renormalise after the area filter, then encode n * 0.5 + 0.5 (OpenGL tangent space)
  for (int y = 0; y < n.rows; ++y)
    for (int x = 0; x < n.cols; ++x) {
      cv::Vec3f& v = n.at<cv::Vec3f>(y, x);
      const float len = std::sqrt(v.dot(v));
      v = len > 1e-8f ? v / len : cv::Vec3f(0, 0, 1);
    }
  n.convertTo(n, CV_32F, 0.5, 0.5);
  io::WriteOptions linear;
  linear.encode = io::ColorSpace::Linear;
  io::writeImage(tex / (p.name + "_normal.png"), n, linear);
  const cv::Mat rough = atSize(maps.roughness, size);
  io::writeImage(tex / (p.name + "_roughness.png"), rough, linear);
  m.maps["albedo"] = tex / (p.name + "_albedo.png");
  m.maps["normal"] = tex / (p.name + "_normal.png");
  m.maps["roughness"] = tex / (p.name + "_roughness.png");
  const cv::Scalar mean = cv::mean(albedo);
  m.homogeneous.albedo =
      ((Vec3d(mean[0], mean[1], mean[2]) + p.albedoOffset.cast<double>()) * p.albedoScale)
          .cwiseMax(0.0)
          .cwiseMin(1.0);
  m.homogeneous.roughness = std::clamp(p.roughness * p.roughnessFactor, 0.0f, 1.0f);
  nlohmann::json params = nlohmann::json::object();
  for (const GraphParameter& gp : g.parameters()) {
    const std::vector<float> v = g.parameter(gp.name);
    params[gp.name] = v.size() == 1 ? nlohmann::json(v[0]) : nlohmann::json(v);
  }
  m.params = params;
}

void writeMaterials(const Context& ctx, const Reads& in, const fs::path& out) {
  fs::create_directories(out / "materials");
  Progress progress("textures", static_cast<int64_t>(ctx.parts.size()));
  parallelFor(0, static_cast<int64_t>(ctx.parts.size()), [&](int64_t i) {
    if (interruptRequested()) return;
    const PartWork& p = ctx.parts[i];
    io::MaterialFileDesc m;
    m.part = p.name;
    m.graph = p.graph;
    m.category = p.category;
    m.homogeneous.albedo = Vec3d::Constant(0.5);
    m.homogeneous.roughness = 0.7;
    switch (p.mode) {
      case PartMode::Fit: {
        writeTextures(in, p, m, out);
        const UvTransform t = p.uv.toTransform();
        m.uv.rotationDeg = t.rotationDeg;
        m.uv.scale = t.scale.cast<double>();
        m.uv.offset = t.offset.cast<double>();
        m.albedoScale = p.albedoScale;
        m.albedoOffset = p.albedoOffset.cast<double>();
        m.roughnessScale = p.roughnessScale * p.roughnessFactor;
        break;
      }
      case PartMode::Homogeneous:
        m.homogeneous.albedo = p.albedo.cast<double>();
        m.homogeneous.roughness = p.roughness;
        break;
      case PartMode::Fixed:
        m.graph = m.category = "homogeneous";
        m.homogeneous.albedo = p.albedo.cast<double>();
        m.homogeneous.roughness = p.roughness;
        m.homogeneous.metallic = p.metallic;
        m.homogeneous.specular = p.specular;
        break;
      case PartMode::Emitter:
        m.graph = m.category = "homogeneous";
        m.homogeneous.albedo = Vec3d::Zero();
        break;
      default:
        m.graph = m.category = "homogeneous";
        break;
    }
    if (p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) {
      m.fitView = p.view;
      m.fitLoss = p.loss;
      m.fitSeconds = p.seconds;
      m.fitExtra["pixels"] = p.pixels;
      m.fitExtra["iterations"] = p.iterations;
      m.fitExtra["refine_loss"] = p.refineLoss;
      if (p.bounceFactor != Vec3f::Ones())  // stage_bounce.cpp
        m.fitExtra["bounce_factor"] = {p.bounceFactor[0], p.bounceFactor[1], p.bounceFactor[2]};
      if (ctx.views.size() > 1)  // how every view sees the part: the largest score is fit.view
        for (const ViewSeen& s : p.seen) {
          nlohmann::json v = {{"view", s.view},
                              {"pixels", s.pixels},
                              {"mean_cosine", s.meanCosine},
                              {"agreement", s.agreement},
                              {"score", s.score},
                              {"exposure", ctx.viewExposure(s.view)}};
          if (s.maskConsistency >= 0) v["mask_consistency"] = s.maskConsistency;
          m.fitExtra["views"].push_back(v);
        }
      if (!p.runnersUp.empty()) m.fitExtra["runners_up"] = p.runnersUp;
      for (const GraphVote& v : p.candidates)
        m.fitExtra["candidates"].push_back({{"graph", v.graph},
                                            {"category", v.category},
                                            {"score", v.weight},
                                            {"votes", v.count}});
      for (const PartWork::Finalist& f : p.finalists)
        m.fitExtra["finalists"].push_back({{"graph", f.graph},
                                           {"category", f.category},
                                           {"vote", f.vote},
                                           {"loss", f.loss},
                                           {"fit_loss", f.fitLoss},
                                           {"pixel_rmse", f.pixelRmse},
                                           {"contrast", f.contrast},
                                           {"contrast_coarse", f.coarseContrast},
                                           {"chroma_spread", f.chroma},
                                           {"chroma_outside", f.chromaOutside},
                                           {"qualifies", f.qualifies},
                                           {"seconds", f.seconds}});
      if (!p.finalists.empty()) {
        m.fitExtra["photo_contrast"] = p.photoContrast;
        m.fitExtra["photo_contrast_coarse"] = p.photoCoarseContrast;
        m.fitExtra["photo_chroma_spread"] = p.photoChroma;
        // the finalists' `loss` is on held-back pixels (fitted on one half, scored on the other)
        m.fitExtra["held_out"] = p.heldOut;
        // the cell size of the `_coarse` contrasts (pixels a side), for whoever reads them
        if (p.photoCoarseContrast > 0)
          m.fitExtra["coarse_contrast_scale"] = in.synthesisOptions().coarseContrastScale;
      }
      if (!p.textureRejected.empty()) m.fitExtra["texture_rejected"] = p.textureRejected;
      if (const auto& given = in.partCategory(static_cast<int>(i)))
        m.fitExtra["category_given"] = *given;  // parts.<name>.category
      if (!p.history.empty()) m.fitExtra["history"] = p.history;
      if (in.baseline() != Baseline::None) m.fitExtra["baseline"] = baselineName(in.baseline());
    } else {
      m.skipped = p.skipped;
    }
    io::writeMaterialJson(out / "materials" / (p.name + ".json"), m, out);
    progress.advance();
  });
  progress.finish();
  checkInterrupted();
}

// The inputs the twin's scene.json names (geometry, photos, label images), copied into the folder
// so that it stands alone; returns the input scene.json with those paths pointing at the copies.
// The geometry is the OBJ with the objects the poses stage moved, moved.
nlohmann::json copyInputs(const Scene& scene, const std::vector<PoseFit>& poses,
                          const fs::path& out) {
  nlohmann::json j = scene.desc.rawJson;
  const fs::path geometry = fs::path("geometry") / scene.desc.geometry.filename();
  if (std::all_of(poses.begin(), poses.end(),
                  [](const PoseFit& f) { return f.pose.isIdentity(); })) {
    copyFile(scene.desc.geometry, out / geometry);
  } else {
    io::ObjMesh obj = io::readObj(scene.desc.geometry);
    for (const PoseFit& f : poses) applyObjectPose(obj, f.object, f.pose, scene.up);
    fs::create_directories((out / geometry).parent_path());
    io::writeObj(out / geometry, obj);
  }
  j["geometry"] = geometry.generic_string();
  for (size_t v = 0; v < scene.views.size(); ++v) {
    const io::ViewDesc& d = scene.desc.views[v];
    const fs::path photo =
        fs::path("photos") / fmt::format("view{}{}", v, d.image.extension().string());
    copyFile(d.image, out / photo);
    j["views"][v]["image"] = photo.generic_string();
    if (d.segments) {
      const fs::path seg =
          fs::path("segments") / fmt::format("view{}{}", v, d.segments->extension().string());
      copyFile(*d.segments, out / seg);
      j["views"][v]["segments"] = seg.generic_string();
    }
  }
  return j;
}

// The recovered lights, every one through its Light::toJson: as lights.json (with the
// exposures) and as the twin scene.json's `lights` (returned); a file a light names (an
// environment image) is copied into the folder's env/.
nlohmann::json writeRecoveredLights(const Context& ctx, const Scene& scene, const fs::path& out) {
  LightJsonContext jc;
  jc.parts = &scene.parts;
  jc.baseDir = out;
  jc.file = (out / "lights.json").string();
  jc.up = scene.up;
  jc.fileRef = [&out](const fs::path& file) {
    const fs::path copy = fs::path("env") / file.filename();
    copyFile(file, out / copy);
    return copy.generic_string();
  };
  std::vector<double> exposure = ctx.exposure;
  if (exposure.empty()) exposure.assign(scene.views.size(), 1.0);
  const nlohmann::json lf = lightsToJson(scene.lights, jc, exposure);
  io::writeJsonFile(out / "lights.json", lf);
  nlohmann::json lights = nlohmann::json::object();
  lights["area"] = lf["emitters"];
  if (lf.contains("environment")) lights["environment"] = lf["environment"];
  return lights;
}

// poses.json: what the poses stage did to each object it fitted (absent where it did not run)
void writePoses(const Context& ctx, const Scene& scene, const fs::path& out) {
  if (ctx.poses.empty()) {
    fs::remove(out / "poses.json");  // a previous run's
    return;
  }
  nlohmann::json objects = nlohmann::json::array();
  for (const PoseFit& f : ctx.poses) {
    const Vec3f& s = f.pose.shift;
    const Vec3f& p = f.pose.pivot;
    objects.push_back({{"object", scene.mesh.objectNames.at(f.object)},
                       {"moved", !f.pose.isIdentity()},
                       {"shift", {s.x(), s.y(), s.z()}},
                       {"yaw_deg", f.pose.yaw * 180 / M_PI},
                       {"scale", f.pose.scale},
                       {"pivot", {p.x(), p.y(), p.z()}},
                       {"labelled_pixels", f.pixels},
                       {"mislabelled_before", f.mismatchBefore},
                       {"mislabelled_after", f.mismatchAfter}});
  }
  io::writeJsonFile(out / "poses.json",
                    {{"about",
                      "objects moved onto the views' labels: p' = pivot + shift + scale R(yaw) "
                      "(p - pivot), R about scene.json up; geometry/ holds the moved OBJ"},
                     {"objects", objects}});
}

// lights.json and the scene.json of the twin
void writeSceneFiles(const Context& ctx, const Reads& in, const fs::path& out) {
  const Scene& scene = in.wholeScene();
  nlohmann::json j = copyInputs(scene, ctx.poses, out);
  j["lights"] = writeRecoveredLights(ctx, scene, out);
  writePoses(ctx, scene, out);
  io::writeJsonFile(out / "scene.json", j);
}

void writeRenders(const Reads& in, const fs::path& out, std::vector<fs::path>& written) {
  const Twin twin = loadTwin(out);
  const PathTracer tracer(twin.scene, twin.materials);
  fs::create_directories(out / "renders");
  for (size_t v = 0; v < twin.scene.views.size(); ++v) {
    checkInterrupted();
    RenderOptions ro;
    ro.spp = in.renderSpp();
    ro.seed = in.seed() + 7919 * v;
    RenderStats stats;
    const double exposure = v < twin.exposure.size() ? twin.exposure[v] : 1.0;
    const cv::Mat image =
        renderTwinView(tracer, twin.scene.views[v].camera, ro, exposure, &stats, in.denoise());
    const fs::path exr = out / "renders" / fmt::format("view{}.exr", v);
    const fs::path png = out / "renders" / fmt::format("view{}.png", v);
    io::writeImage(exr, image);
    io::writeImage(png, image);
    written.push_back(exr);
    written.push_back(png);
    spdlog::info("render view {}: {}x{} at {} spp{} in {:.1f} s", v, image.cols, image.rows, ro.spp,
                 in.denoise() ? ", denoised" : "", stats.seconds);
  }
}

}  // namespace

namespace {

class ExportStage : public Stage {
 public:
  explicit ExportStage(std::vector<std::string> after) : Stage("export") {
    // 9: fit.coarse_contrast_scale in the materials files; 10: maps below the fit's map size are
    // the graph at that size, area-downsampled (writeTextures)
    decl.version = 10;
    decl.scene = {""};
    decl.options = {"texture_size", "preset",     "render_spp", "denoise",
                    "baseline",     "write_gltf", "library",    "selection"};
    decl.after = std::move(after);
    decl.writes = {"OUT/materials/*.json",
                   "OUT/textures/*",
                   "OUT/lights.json",
                   "OUT/scene.json",
                   "OUT/poses.json",
                   "OUT/geometry (the OBJ, objects moved as `poses` found), photos, segments, "
                   "env (copies)",
                   "OUT/renders/*",
                   "OUT/twin.gltf, twin.bin"};
  }

  bool compute(Context& ctx, const Reads& in, int) override {
    const fs::path& out = in.out();
    writeMaterials(ctx, in, out);
    writeSceneFiles(ctx, in, out);
    std::vector<fs::path> written = {out / "scene.json", out / "lights.json"};
    if (!ctx.poses.empty()) written.push_back(out / "poses.json");
    for (const PartWork& p : ctx.parts) written.push_back(out / "materials" / (p.name + ".json"));
    writeRenders(in, out, written);
    if (in.writeGltf()) {
      checkInterrupted();
      const GltfExportSummary g = writeTwinGltf(loadTwin(out), out);
      spdlog::info("glTF: {} meshes, {} materials, {} images, {} emitters", g.meshes, g.materials,
                   g.images, g.emitters);
      written.push_back(out / "twin.gltf");
      written.push_back(out / "twin.bin");
    }
    written_.clear();
    for (const fs::path& f : written) written_.push_back(fs::relative(f, out).generic_string());
    return true;
  }
  // the files written, so that a rerun whose files were deleted writes them again
  void save(const Context&, int, Archive& a) const override {
    a.put<uint64_t>(written_.size());
    for (const std::string& f : written_) a.putString(f);
  }
  bool load(Context&, const Reads& in, int, Archive& a) override {
    const uint64_t n = a.get<uint64_t>();
    bool complete = true;
    for (uint64_t i = 0; i < n; ++i) complete = fs::exists(in.out() / a.getString()) && complete;
    return complete;
  }

 private:
  std::vector<std::string> written_;
};

}  // namespace

std::unique_ptr<Stage> makeExportStage(std::vector<std::string> after) {
  return std::make_unique<ExportStage>(std::move(after));
}

}  // namespace ps::pipeline
